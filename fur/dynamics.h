// Fur dynamics on the shared vertex array (seed 3.2-3.3): a gravity pose, a wind pose,
// and the per-frame blend of the two.
//
// A pose is one position per fur vertex, laid out like FurGeometry::positions: vertex
// I = i + s*N, so base vertex i's chain of nodes is I = i, i+N, ..., i+(S-1)N, node 0 on
// the base surface (never moved). Every function is a pure loop over base vertices
// [begin, end): call it once over all of them, or split the range across threads (the
// ranges touch disjoint outputs). None allocates; outputs are preallocated by the
// caller and may not alias inputs unless stated.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "fur/fur_geometry.h"
#include "fur/fur_params.h"

namespace pelt::fur {

// How eq. 2's theta = dot(V, G) * RN / stability is read (V = unit direction of the
// chain segment leaving the current node, G = unit gravity direction, RN = nodes
// remaining beyond the current node, S-1-k at node k; axis = cross(V, G)).
//   lever    (default): the dot factor is taken as the lever arm |V x G| = sin(angle):
//            largest for a horizontal strand, zero for one along or against G.
//   seed_dot: the formula as printed, dot(V, G) = cos(angle): no bend for a horizontal
//            strand and none (clamped from negative) for strands pointing up.
// Both multiply by params.strength, and both clamp theta to [0, angle(V, G)] so a
// segment swings toward gravity but never past it: stability = 0 (or a huge strength)
// lets every segment hang straight along G, never NaN, unless that is into the surface
// (see apply_gravity).
enum class GravityLaw { lever, seed_dot };

// Bends each chain node by node (seed Fig. 9): at node k = 0..S-2, rotate nodes
// k+1..S-1 about node k, axis cross(V, G), by theta. Rotations keep every segment's
// length (to float rounding). Nothing bends when G or strength is 0, when V is
// parallel or antiparallel to G, or when stability is huge. After node k's bend, a segment k
// lower than kMinFurElevation (fur/fur_geometry.h) above the tangent plane of its base
// vertex's `surface_normals` entry (one per base vertex, unit; FurGeometry::base_normals) is
// raised to it along its heading, nodes k+1.. turning with it, so gravity lays fur down on
// the surface, never through it; chains that stay above it come out bit for bit as without
// the rule. `rest` and `out` have S*N entries; out may equal rest (in place). Chains longer
// than 128 nodes (beyond FurParams' range) bend their first 128 nodes only.
// `authored_layers` (FurParams::authored_shells; 0 or S: the formula as printed) is the
// node count the gravity parameters were chosen for. Eq. 2's theta grows with RN, so a
// chain of S nodes turns its tip by sum theta ~ S^2 / 2 in all: the same fur re-sliced into
// 64 layers instead of 16 would hang 16 times as far. With A = authored_layers != S every
// theta is scaled by A (A - 1) / (S (S - 1)), the ratio of the two counts' sums of RN, so the
// chain's total bend is the authored chain's (before the clamp below) whatever S is, and
// more layers resolve the same curve more finely. With A = S the scale is exactly 1.
// Whether apply_gravity moves any node: not for a zero direction or strength, nor for
// infinitely stiff fur. Where it does not, its pose is the rest pose bit for bit, and the
// renderer runs no gravity pass.
bool gravity_bends(const GravityParams& gravity);

void apply_gravity(std::span<const glm::vec3> rest, std::span<const glm::vec3> surface_normals,
                   uint32_t base_vertex_count, uint32_t layers, uint32_t authored_layers,
                   const GravityParams& gravity, GravityLaw law, std::span<glm::vec3> out, uint32_t begin,
                   uint32_t end);

// Wind force field: one force per base vertex, a travelling gust wave,
//   F_i(t) = d * strength * (1 + gust_scale * sin(2 pi (gust_frequency * t - (q_i.d) / L)))
// d = unit wind direction, q_i = base vertex - bounding centre, L = 2 R (wavelength:
// one gust crest spans the object and moves along d at L * gust_frequency units/s).
// gust_scale in [0, 1] keeps the factor in [0, 2]. Build once per object (allocates);
// forces() per frame does not.
struct WindField {
  glm::vec3 direction{1.0f, 0.0f, 0.0f};  // unit
  float strength = 0.0f, gust_frequency = 0.0f, gust_scale = 0.0f;
  std::vector<float> phase;  // (q_i.d) / L per base vertex, in wavelengths
  glm::vec3 phase_input{0.0f};  // WindParams::direction as given, that `phase` was made from

  // Fills out[begin, end) with F_i(time_seconds).
  void forces(double time_seconds, std::span<glm::vec3> out, uint32_t begin, uint32_t end) const;
};
WindField make_wind_field(const FurGeometry& geometry, const WindParams& wind);
// `field` for `wind`, in place: the phases, which depend on the direction alone, are made
// again only when it changed (or the geometry's vertex count did), and their array keeps its
// storage, so a wind whose strength or direction is animated allocates nothing per frame.
void update_wind_field(const FurGeometry& geometry, const WindParams& wind, WindField& field);

// Rotates each whole chain once about its root (seed Fig. 11): axis cross(n_i, F_i),
// angle theta = phi * (1 - exp(-|F_i|)) where phi = angle(n_i, F_i): the strand leans
// toward the force, further for a stronger force, never past it (|F| = 1 goes 63% of
// the way). n_i = `normals` (pass FurGeometry::growth so combed fur bends from its
// combed direction). No rotation for F = 0, F parallel or antiparallel to n, or
// non-finite F. On a windward face phi passes 90 degrees, and so can theta: then each
// segment of the turned chain, root to tip, that lies lower than kMinFurElevation
// (fur/fur_geometry.h) above the tangent plane of `surface_normals[i]` (unit;
// FurGeometry::base_normals) is raised to it along its heading, the nodes beyond it turning
// with it: the wind flattens fur onto the surface, never through it, and chains that stay
// above it come out bit for bit as without the rule. `pose` is the pose to push (the rest or
// the gravity pose, both above the surface); out may equal pose. Chains longer than 128
// nodes (beyond FurParams' range) are raised over their first 128 nodes only.
void apply_wind(std::span<const glm::vec3> pose, std::span<const glm::vec3> normals,
                std::span<const glm::vec3> surface_normals, std::span<const glm::vec3> forces,
                uint32_t base_vertex_count, uint32_t layers, std::span<glm::vec3> out, uint32_t begin,
                uint32_t end);

// out[I] = a[I] + (b[I] - a[I]) * t for fur vertices I in [begin, end) (a flat range,
// not base vertices). t = 0 gives exactly a, t = 1 exactly b, and a coordinate equal in a and b
// comes out unchanged for every t (the roots stay on the base mesh).
void lerp_poses(std::span<const glm::vec3> a, std::span<const glm::vec3> b, float t,
                std::span<glm::vec3> out, size_t begin, size_t end);
inline void lerp_poses(std::span<const glm::vec3> a, std::span<const glm::vec3> b, float t,
                       std::span<glm::vec3> out) {
  lerp_poses(a, b, t, out, 0, out.size());
}

// Seed Fig. 12: animation data 1 (gravity pose) at t = 0, data 2 (wind pose) at t = 1.
// pelt swings between them smoothly and periodically:
//   t(x) = 0.5 - 0.5 cos(2 pi x / period), t(0) = 0,
// x and period in one unit (the renderer passes seconds). period <= 0 or non-finite gives 0
// (static gravity pose).
float animation_t(double x, double period);

// Unit strand tangent per fur vertex from a deformed pose, for Kajiya-Kay: central
// difference p[k+1] - p[k-1] along the chain, one-sided at the root and tip; where the
// chain has zero length (or is not finite) the growth direction. out has S*N entries.
void strand_tangents(std::span<const glm::vec3> pose, std::span<const glm::vec3> growth,
                     uint32_t base_vertex_count, uint32_t layers, std::span<glm::vec3> out,
                     uint32_t begin, uint32_t end);

// The llvmpipe harness's animation (its README): with h = s/(S-1), bend = h^2 * fur length,
// tang(a, n) = a - n (a.n), q = base vertex - centre:
//   p0 = rest + tang((0,-1,0), n) * 0.4 bend
//   p1 = rest + tang(normalize(1, 0.2, 0.6), n) * 0.8 bend * (0.75 + 0.25 sin(3 (q.x + q.z) / R))
// rest = geometry.positions, n = geometry.base_normals. With geometry built from the
// harness's mesh with shells = 16 and length = 0.1 this is its scene.
void llvmpipe_poses(const FurGeometry& geometry, std::span<glm::vec3> p0, std::span<glm::vec3> p1);
// t = 0.5 + 0.5 sin(0.1 frame).
float llvmpipe_animation_t(int frame);

}  // namespace pelt::fur
