// Procedural meshes named by a spec string `name:N` (box, teapot, sphere, plane), so a
// scene or a test can ask for geometry without shipping a file.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "raster/mesh.h"
#include "tools/io/budget.h"

namespace pelt::io {

enum class BuiltinShape { box, teapot, sphere, plane };

// Largest accepted N per shape: keeps a typo such as `teapot:5000` from asking for
// gigabytes (teapot:N has 32 (N+1)^2 points before welding, box:N 6 (N+1)^2).
inline constexpr int kMaxBoxN = 1024;
inline constexpr int kMaxTeapotN = 256;
inline constexpr int kMaxSphereN = 2048;
inline constexpr int kMaxPlaneN = 1024;
// sphere:N has N/2 rings; below 4 the "sphere" would have no ring between the poles.
inline constexpr int kMinSphereN = 4;

struct BuiltinSpec {
  BuiltinShape shape;
  int n;
};

// True when `text` has the shape of a built-in spec rather than a file path: a lowercase
// word, a colon, and no path separator or dot after it ("box:7", "cube:3", "box:"). A
// scene's `mesh` string is parsed as a built-in exactly when this holds.
bool looks_like_builtin_spec(std::string_view text);

// Parses `name:N`. Throws InputError(file, field, reason) for an unknown name (with the
// nearest known name), a missing, non-integer, zero, negative or too large N.
BuiltinSpec parse_builtin_spec(std::string_view spec, const std::string& file = "",
                               const std::string& field = "");

// The mesh for a spec; positions, unit normals (pelt::compute_vertex_normals), uvs and
// counter-clockwise-from-outside triangles.
Mesh make_builtin_mesh(std::string_view spec, const std::string& file = "",
                       const std::string& field = "");
Mesh make_builtin_mesh(const BuiltinSpec& spec);
// The same after checking builtin_triangle_count(spec) against budget.max_faces: refused
// with InputError(file, field, count, budget, --max-faces) before anything is generated.
Mesh make_builtin_mesh(const BuiltinSpec& spec, const Budget& budget, const std::string& file = "",
                       const std::string& field = "");

// Triangles a spec generates, from N alone: box 12 N^2, plane 2 N^2, sphere 2 N (N/2 - 1);
// teapot 64 N^2 (32 patches of N x N quads), the count generated before the triangles that
// collapse at the patches' poles are dropped (so a bound on the final mesh, exact for
// what is allocated).
uint64_t builtin_triangle_count(const BuiltinSpec& spec);

// Cube [-1,1]^3; each face an (n+1)x(n+1) grid welded across faces; quad (i,j) gives
// (p00,p10,p11),(p00,p11,p01). UVs: the body-diagonal planar projection below.
Mesh make_box(int n);

// Utah teapot: every patch sampled at (i/n, j/n), welded (1e-5 x control-point radius),
// triangles with a repeated index or zero area dropped, unreferenced vertices removed,
// winding made outward, converted to y-up (x,y,z) -> (x,z,-y) and centred on its
// bounding-box centre. UVs: the body-diagonal planar projection below.
Mesh make_teapot(int n);

// UV sphere of radius 1: n segments around y, n/2 rings; u = longitude / 2pi, v = 1 at the
// north pole (+y) down to 0 at the south pole. Split like an exporter's texture seam: the
// meridian u = 0 is repeated with u = 1 (the same positions bit for bit), and each pole is n
// vertices, one per fan triangle, at u = (s + 1/2) / n. Closed by position, not by index;
// normals summed over every copy at a position (NormalSharing::per_position).
Mesh make_sphere(int n);

// The square [-1,1]^2 in the xz plane at y = 0, normal +y, n x n quads;
// uv = ((x+1)/2, (z+1)/2).
Mesh make_plane(int n);

// Planar texture projection along the body diagonal (the llvmpipe anchor harness's
// convention): q = p - centre, u = k q.e1, v = k q.e2 with e1 = (1,-1,0)/sqrt2,
// e2 = (1,1,-2)/sqrt6, k = 2.449490 sqrt(3) / radius. No box face is parallel to it,
// so it is continuous across welded vertices.
void body_diagonal_uvs(Mesh& mesh, const glm::dvec3& centre, double radius);

// One bicubic Bezier patch: control point [r][c] is points[r*4+c].
using BezierPatch = std::array<glm::dvec3, 16>;

// Parses "bpt" text (patch count, then per patch "3 3" and 16 "x y z" lines). Throws
// InputError naming `file` and the patch/point at fault.
std::vector<BezierPatch> parse_bpt(std::string_view text, const std::string& file);

// The 32 teapot patches embedded in the library from tools/data/teapot.bpt.
const std::vector<BezierPatch>& teapot_patches();

// Surface point of a patch at (u, v): sum over r,c of B_r(u) B_c(v) P[r][c].
glm::dvec3 eval_bezier_patch(const BezierPatch& patch, double u, double v);

}  // namespace pelt::io
