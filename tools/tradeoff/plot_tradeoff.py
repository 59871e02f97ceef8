# Draws `pelt tradeoff`'s plot: error (rmse, log) against frame time (ms, log), every
# setting labelled, the Pareto front as a step line, the presets highlighted.
# Embedded in the pelt binary and run as:
#   python3 -c SCRIPT TRADEOFF.csv OUT.png TITLE FRONT
# FRONT lists the CSV's data-row indices (0-based) on the Pareto front, comma-separated.
# Exit codes: 0 plot written, 3 matplotlib missing, 4 bad arguments or CSV.
# With PELT_PLOT_LABEL_BOXES=FILE, each label's box (display pixels: x0 y0 x1 y1, one a line)
# is also written to FILE, so a test can check that no two labels overlap.
import csv
import math
import os
import sys

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as e:
    sys.stderr.write(f"matplotlib is not available to {sys.executable}: {e}\n")
    sys.exit(3)


def fail(msg):
    sys.stderr.write(msg + "\n")
    sys.exit(4)


def main(argv):
    if len(argv) != 5:
        fail("usage: plot TRADEOFF.csv OUT.png TITLE FRONT")
    csv_path, png_path, title, front_arg = argv[1:]
    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        fail(f"{csv_path}: no rows")
    try:
        front = {int(i) for i in front_arg.split(",") if i}
        pts = [(float(r["ms_median"]), float(r["rmse"]), r["knob"], r["setting"]) for r in rows]
    except (KeyError, ValueError) as e:
        fail(f"{csv_path}: {e}")
    if any(i < 0 or i >= len(pts) for i in front):
        fail(f"front index out of range 0..{len(pts) - 1}")

    # rmse 0 (the reference, and anything that matches it byte for byte) has no place on a
    # log axis: such points sit on a floor line below the smallest non-zero error.
    positive = [p[1] for p in pts if p[1] > 0]
    floor = min(positive) / 4 if positive else 1e-4
    y = lambda e: e if e > 0 else floor

    fig, ax = plt.subplots(figsize=(10, 6.5), dpi=110)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.axhline(floor, color="0.75", linestyle=":", linewidth=1)
    ax.text(min(p[0] for p in pts), floor, " rmse 0 (same bytes as the reference)",
            va="bottom", ha="left", fontsize=7, color="0.45")

    fr = sorted((pts[i][0], y(pts[i][1])) for i in front)
    if fr:
        # A step line: the best error reachable within each time budget.
        ax.step([p[0] for p in fr], [p[1] for p in fr], where="post", color="tab:red",
                linewidth=1.2, alpha=0.8, label="Pareto front", zorder=1)

    kinds = {
        "reference": dict(marker="*", s=140, color="black", label="reference"),
        "preset": dict(marker="D", s=60, color="tab:orange", edgecolors="black", label="preset"),
        "default": dict(marker="s", s=50, color="tab:green", edgecolors="black", label="default (scene)"),
    }
    plain = dict(marker="o", s=22, color="tab:blue", label="one knob changed")
    seen = set()
    for i, (ms, e, knob, setting) in enumerate(pts):
        style = dict(kinds.get(knob, plain))
        label = style.pop("label")
        if label in seen:
            label = None
        else:
            seen.add(label)
        ax.scatter([ms], [y(e)], zorder=3, label=label,
                   linewidths=1.5 if i in front else 0.5, **style)

    # Settings with the same measurement share one label, so stacked points stay readable.
    labels = {}
    for i, (ms, e, knob, setting) in enumerate(pts):
        labels.setdefault((ms, y(e)), []).append((i, f"{knob}={setting}"))

    # Room around the points for their labels (most settings sit near the top, at the
    # default's error).
    xs = [p[0] for p in pts]
    ys = [y(p[1]) for p in pts]
    ax.set_xlim(min(xs) / 1.5, max(xs) * 1.5)
    ax.set_ylim(min(ys) / 1.5, max(ys) * 2.5)
    ax.set_xlabel("median frame time (ms, log)")
    ax.set_ylabel("RMSE against the reference (8-bit sRGB, log)")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", linewidth=0.3, alpha=0.5)
    ax.legend(fontsize=8, loc="upper right")
    fig.tight_layout()
    place_labels(fig, ax, labels, front)
    fig.savefig(png_path, format="png")
    return 0


def place_labels(fig, ax, labels, front):
    """Puts each label where it overlaps no other label, no marker and not the legend.

    A sweep's settings that leave the image unchanged pile up at one error within a few
    milliseconds, so labels at fixed offsets covered each other. Greedy placement in
    display coordinates: the Pareto front's labels first, then the others in time order;
    each tries offsets on rings of growing radius around its point and takes the first
    free one, with a leader line when it had to move away. A label with no free spot
    within the largest ring is drawn at its point anyway (readable beats missing)."""
    renderer = fig.canvas.get_renderer()
    to_px = ax.transData.transform
    points_px = fig.dpi / 72.0
    axes_box = ax.get_window_extent(renderer)
    taken = []
    placed = []
    # Markers as small boxes, so labels do not cover them.
    for (ms, e) in labels:
        cx, cy = to_px((ms, e))
        r = 4 * points_px
        taken.append((cx - r, cy - r, cx + r, cy + r))
    legend = ax.get_legend()
    if legend is not None:
        lb = legend.get_window_extent(renderer)
        taken.append((lb.x0, lb.y0, lb.x1, lb.y1))

    def free(box):
        x0, y0, x1, y1 = box
        if x0 < axes_box.x0 or x1 > axes_box.x1 or y0 < axes_box.y0 or y1 > axes_box.y1:
            return False
        return all(x1 <= t[0] or x0 >= t[2] or y1 <= t[1] or y0 >= t[3] for t in taken)

    rings = [5, 12, 20, 30, 42, 56, 72, 90, 110]
    angles = [0, 30, -30, 60, -60, 90, -90, 150, -150, 180, 120, -120]

    def order(item):
        (ms, e), names = item
        return (0 if any(i in front for i, _ in names) else 1, ms, e)

    for (ms, e), names in sorted(labels.items(), key=order):
        texts = [n for _, n in names]
        text = ", ".join(texts) if len(texts) <= 3 else ", ".join(texts[:3]) + f" +{len(texts) - 3}"
        ann = ax.annotate(text, (ms, e), xytext=(5, 0), textcoords="offset points", fontsize=6.5,
                          va="center", ha="left")
        w = ann.get_window_extent(renderer)
        tw, th = w.width, w.height
        cx, cy = to_px((ms, e))
        chosen = None
        for r in rings:
            for a in angles:
                dx = r * math.cos(math.radians(a))
                dy = r * math.sin(math.radians(a))
                # The text starts at the offset on the right, ends there on the left.
                left = dx >= 0
                x0 = cx + dx * points_px if left else cx + dx * points_px - tw
                y0 = cy + dy * points_px - th / 2
                box = (x0, y0, x0 + tw, y0 + th)
                if free(box):
                    chosen = (dx, dy, left, box)
                    break
            if chosen:
                break
        if chosen is None:
            chosen = (5, 0, True, (cx, cy - th / 2, cx + tw, cy + th / 2))
        dx, dy, left, box = chosen
        ann.set_position((dx, dy))
        ann.set_ha("left" if left else "right")
        if math.hypot(dx, dy) > 6:
            ax.annotate("", (ms, e), xytext=(dx, dy), textcoords="offset points",
                        arrowprops=dict(arrowstyle="-", color="0.6", linewidth=0.4, shrinkA=0, shrinkB=2))
        taken.append(box)
        drawn = ann.get_window_extent(renderer)  # where the text really is, for the test
        placed.append((drawn.x0, drawn.y0, drawn.x1, drawn.y1))
    boxes_path = os.environ.get("PELT_PLOT_LABEL_BOXES")
    if boxes_path:
        with open(boxes_path, "w") as f:
            for b in placed:
                f.write(" ".join(f"{v:.2f}" for v in b) + "\n")


if __name__ == "__main__":
    sys.exit(main(sys.argv))
