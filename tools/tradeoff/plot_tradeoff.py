# Draws `pelt tradeoff`'s plot: error (rmse, log) against frame time (ms, log), every
# setting labelled, the Pareto front as a step line, the presets highlighted.
# Embedded in the pelt binary and run as:
#   python3 -c SCRIPT TRADEOFF.csv OUT.png TITLE FRONT
# FRONT lists the CSV's data-row indices (0-based) on the Pareto front, comma-separated.
# Exit codes: 0 plot written, 3 matplotlib missing, 4 bad arguments or CSV.
import csv
import math
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
    for ms, e, knob, setting in pts:
        labels.setdefault((ms, y(e)), []).append(f"{knob}={setting}")
    # Settings that leave the image unchanged line up at one error: their labels are
    # staggered above and below the line, in time order.
    at_error = {}
    for (ms, e), names in sorted(labels.items()):
        k = at_error.get(e, 0)
        at_error[e] = k + 1
        dy = (3 + 8 * (k // 2)) * (1 if k % 2 == 0 else -1.6)
        text = ", ".join(names) if len(names) <= 3 else ", ".join(names[:3]) + f" +{len(names) - 3}"
        ax.annotate(text, (ms, e), xytext=(4, dy), textcoords="offset points", fontsize=6.5,
                    arrowprops=dict(arrowstyle="-", color="0.6", linewidth=0.4) if k else None)

    ax.set_xlabel("median frame time (ms, log)")
    ax.set_ylabel("RMSE against the reference (8-bit sRGB, log)")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", linewidth=0.3, alpha=0.5)
    ax.legend(fontsize=8, loc="upper right")
    fig.tight_layout()
    fig.savefig(png_path, format="png")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
