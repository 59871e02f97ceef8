// glTF 2.0 (.gltf with external or data-URI buffers, and .glb) through tinygltf.
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include <tiny_gltf.h>

#include "tools/io/image_io.h"
#include "tools/io/input_error.h"
#include "tools/io/json_fields.h"
#include "tools/io/mesh_loader_detail.h"
#include "tools/io/pixels.h"

namespace pelt::io::detail {
namespace {

constexpr int kMaxNodeDepth = 256;  // deeper than any real scene; stops runaway recursion

class GltfReader {
 public:
  GltfReader(const tinygltf::Model& model, std::string file, std::filesystem::path dir, const Budget& budget)
      : model_(model), file_(std::move(file)), dir_(std::move(dir)), budget_(budget) {}

  // Triangles the default scene makes, from the accessors' counts alone (no buffer is
  // read), every mesh instance counted; saturating. A node reached twice through a DAG of
  // children is counted twice, as read() would draw it twice, but computed once, so a
  // file that nests instances exponentially is counted in linear time and refused.
  // Broken references count 0 here: read() names them.
  uint64_t triangle_count() const {
    std::vector<uint64_t> memo(model_.nodes.size(), kUncounted);
    uint64_t total = 0;
    for (int root : scene_roots()) total = sat_add(total, count_node(root, 0, memo));
    return total;
  }

  LoadedMesh read() {
    const std::vector<int> roots = scene_roots();
    parents_.assign(model_.nodes.size(), -1);
    world_.assign(model_.nodes.size(), std::nullopt);
    for (size_t i = 0; i < model_.nodes.size(); ++i)
      for (int c : model_.nodes[i].children)
        if (c >= 0 && c < static_cast<int>(parents_.size()) && parents_[size_t(c)] < 0)
          parents_[size_t(c)] = static_cast<int>(i);
    std::vector<int> on_path(model_.nodes.size(), 0);
    for (int root : roots) visit(root, glm::dmat4(1.0), 0, on_path);
    if (!hidden_.empty())
      out_.warnings.push_back(hidden_[0] + (hidden_.size() > 1 ? " and " + std::to_string(hidden_.size() - 1) +
                                                                     " more nodes are" : " is") +
                              " scaled to a point or a line: not drawn");
    if (out_.mesh.indices.empty())
      throw InputError(file_, "", "the default scene has no triangles");
    settle_uvs(out_, std::move(uv_missing_), "no TEXCOORD_0 in", uvless_);
    // Each primitive keeps its material's maps; a file whose primitives all use one set of
    // maps (or none) needs no list per triangle. Until 2026-11-27 the first primitive's maps
    // were drawn on the whole mesh.
    if (std::any_of(sets_.begin(), sets_.end(), [](const MeshMaps& m) { return m.any(); })) {
      out_.maps = std::move(sets_);
      if (out_.maps.size() > 1) out_.triangle_maps = std::move(triangle_maps_);
      if (unmaterialed_triangles_ > 0)
        out_.warnings.push_back(std::to_string(unmaterialed_triangles_) +
                                (unmaterialed_triangles_ == 1 ? " triangle" : " triangles") +
                                " of primitives without a material (" +
                                unmaterialed_ + ", ...) are drawn without the file's maps and alpha");
    }
    // Every vertex has a normal now, the file's or a flat one: only zero-length ones are replaced.
    finish_normals(out_, true, true, NormalSharing::per_vertex);
    return std::move(out_);
  }

 private:
  std::vector<int> scene_roots() const {
    if (!model_.scenes.empty()) {
      const int s = model_.defaultScene >= 0 ? model_.defaultScene : 0;
      if (s >= static_cast<int>(model_.scenes.size()))
        throw InputError(file_, "scene", "default scene " + std::to_string(s) + " does not exist");
      return model_.scenes[s].nodes;
    }
    // No scene: every node that is nobody's child is a root.
    std::vector<bool> is_child(model_.nodes.size(), false);
    for (const auto& n : model_.nodes)
      for (int c : n.children)
        if (c >= 0 && c < static_cast<int>(is_child.size())) is_child[c] = true;
    std::vector<int> roots;
    for (size_t i = 0; i < is_child.size(); ++i)
      if (!is_child[i]) roots.push_back(static_cast<int>(i));
    return roots;
  }

  static constexpr uint64_t kUncounted = UINT64_MAX - 1;
  static constexpr uint64_t kOnPath = UINT64_MAX - 2;

  uint64_t count_node(int node, int depth, std::vector<uint64_t>& memo) const {
    if (node < 0 || node >= static_cast<int>(model_.nodes.size()) || depth > kMaxNodeDepth) return 0;
    uint64_t& m = memo[size_t(node)];
    if (m == kOnPath) return 0;  // a cycle: read() reports it
    if (m != kUncounted) return m;
    m = kOnPath;
    const tinygltf::Node& n = model_.nodes[size_t(node)];
    uint64_t total = count_mesh(n.mesh);
    for (int c : n.children) total = sat_add(total, count_node(c, depth + 1, memo));
    // The two sentinels are not counts: a total that reaches them has saturated.
    if (total == kOnPath || total == kUncounted) total = UINT64_MAX;
    m = total;  // memo is not resized during the recursion, so `m` is still valid
    return total;
  }

  uint64_t count_mesh(int mesh_index) const {
    if (mesh_index < 0 || mesh_index >= static_cast<int>(model_.meshes.size())) return 0;
    uint64_t total = 0;
    for (const tinygltf::Primitive& prim : model_.meshes[size_t(mesh_index)].primitives) {
      int accessor = prim.indices;
      if (accessor < 0) {
        const auto it = prim.attributes.find("POSITION");
        accessor = it == prim.attributes.end() ? -1 : it->second;
      }
      if (accessor < 0 || accessor >= static_cast<int>(model_.accessors.size())) continue;
      const uint64_t count = model_.accessors[size_t(accessor)].count;
      const bool list = prim.mode == TINYGLTF_MODE_TRIANGLES;
      total = sat_add(total, list ? count / 3 : count >= 3 ? count - 2 : 0);
    }
    return total;
  }

  // A node's matrix, like a joint's inverse bind matrix, is a translation, rotation and scale
  // (decomposable, the specification says): its last row is 0, 0, 0, 1, made exact here when it
  // is within an exporter's float rounding. Another would be a projection, whose w pelt drops.
  void make_affine(glm::dmat4& m, const std::string& field) const {
    constexpr double kRounding = 1e-6;
    if (std::abs(m[0][3]) > kRounding || std::abs(m[1][3]) > kRounding || std::abs(m[2][3]) > kRounding ||
        std::abs(m[3][3] - 1.0) > kRounding)
      throw InputError(file_, field, "the last row (elements 3, 7, 11, 15) must be 0, 0, 0, 1: the matrix is affine");
    m[0][3] = m[1][3] = m[2][3] = 0.0;
    m[3][3] = 1.0;
  }

  glm::dmat4 local_transform(const tinygltf::Node& n, const std::string& where) const {
    if (n.matrix.size() == 16) {
      glm::dmat4 m;
      std::memcpy(glm::value_ptr(m), n.matrix.data(), sizeof(double) * 16);  // column-major
      for (int k = 0; k < 16; ++k)
        if (!std::isfinite(n.matrix[k])) throw InputError(file_, where + ".matrix", "value is not finite");
      make_affine(m, where + ".matrix");
      return m;
    }
    if (!n.matrix.empty()) throw InputError(file_, where + ".matrix", "must have 16 numbers");
    glm::dmat4 m(1.0);
    if (n.translation.size() == 3)
      m[3] = glm::dvec4(n.translation[0], n.translation[1], n.translation[2], 1.0);
    glm::dmat4 r(1.0);
    if (n.rotation.size() == 4) {
      // glTF stores (x, y, z, w); glm's constructor takes (w, x, y, z).
      const glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
      if (!(glm::length(q) > 0.0)) throw InputError(file_, where + ".rotation", "zero quaternion");
      r = glm::mat4_cast(glm::normalize(q));
    }
    glm::dmat4 s(1.0);
    if (n.scale.size() == 3) {
      s[0][0] = n.scale[0];
      s[1][1] = n.scale[1];
      s[2][2] = n.scale[2];
    }
    const glm::dmat4 result = m * r * s;
    for (int c = 0; c < 4; ++c)
      for (int k = 0; k < 4; ++k)
        if (!std::isfinite(result[c][k])) throw InputError(file_, where, "transform is not finite");
    return result;
  }

  void visit(int node, const glm::dmat4& parent, int depth, std::vector<int>& on_path) {
    const std::string where = "nodes[" + std::to_string(node) + "]";
    if (node < 0 || node >= static_cast<int>(model_.nodes.size()))
      throw InputError(file_, where, "node does not exist");
    if (on_path[node]) throw InputError(file_, where, "node is its own ancestor (cycle)");
    if (depth > kMaxNodeDepth) throw InputError(file_, where, "node hierarchy is too deep");
    const tinygltf::Node& n = model_.nodes[node];
    const glm::dmat4 world = parent * local_transform(n, where);
    if (n.mesh >= 0) add_mesh(node, world);
    on_path[node] = 1;
    for (int c : n.children) visit(c, world, depth + 1, on_path);
    on_path[node] = 0;
  }

  // A view of one accessor's elements: base pointer, stride, count, components.
  struct View {
    const uint8_t* data;
    size_t stride;
    size_t count;
    int components;
    int component_type;
    bool normalized;
  };

  View view_of(int accessor_index, const std::string& where) const {
    if (accessor_index < 0 || accessor_index >= static_cast<int>(model_.accessors.size()))
      throw InputError(file_, where, "accessor " + std::to_string(accessor_index) + " does not exist");
    const tinygltf::Accessor& a = model_.accessors[accessor_index];
    const std::string aw = "accessors[" + std::to_string(accessor_index) + "]";
    if (a.sparse.isSparse) throw InputError(file_, aw, "sparse accessors are not supported");
    if (a.bufferView < 0 || a.bufferView >= static_cast<int>(model_.bufferViews.size()))
      throw InputError(file_, aw, "has no valid bufferView");
    const tinygltf::BufferView& bv = model_.bufferViews[a.bufferView];
    if (bv.buffer < 0 || bv.buffer >= static_cast<int>(model_.buffers.size()))
      throw InputError(file_, aw, "bufferView refers to a missing buffer");
    const auto& buf = model_.buffers[bv.buffer].data;
    const int comps = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
    const int csize = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType));
    if (comps <= 0 || csize <= 0) throw InputError(file_, aw, "unknown type or componentType");
    const size_t elem = static_cast<size_t>(comps) * csize;
    const size_t stride = bv.byteStride ? bv.byteStride : elem;
    if (stride < elem) throw InputError(file_, aw, "byteStride is smaller than one element");
    if (bv.byteOffset + bv.byteLength > buf.size())
      throw InputError(file_, aw, "bufferView runs past the end of its buffer");
    if (a.count > 0 && a.byteOffset + (a.count - 1) * stride + elem > bv.byteLength)
      throw InputError(file_, aw, "accessor runs past the end of its bufferView");
    return View{buf.data() + bv.byteOffset + a.byteOffset, stride, a.count, comps, a.componentType,
                a.normalized};
  }

  // Reads component k of element i as a float (floats as is; normalized integers mapped
  // to [0,1] as the glTF spec says for TEXCOORD).
  static float component(const View& v, size_t i, int k) {
    const uint8_t* p = v.data + i * v.stride;
    switch (v.component_type) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float f;
        std::memcpy(&f, p + 4 * k, 4);
        return f;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return p[k] / 255.0f;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t s;
        std::memcpy(&s, p + 2 * k, 2);
        return s / 65535.0f;
      }
      default: return NAN;  // rejected by the callers' type checks before we get here
    }
  }

  // Component k of element i as an unsigned integer (indices, joints): the callers have
  // checked the type is UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT.
  static uint32_t index_at(const View& v, size_t i, int k = 0) {
    const uint8_t* p = v.data + i * v.stride;
    switch (v.component_type) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return p[k];
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t s;
        std::memcpy(&s, p + 2 * k, 2);
        return s;
      }
      default: {
        uint32_t u;
        std::memcpy(&u, p + 4 * k, 4);
        return u;
      }
    }
  }

  // How a node's linear transform takes normals: its inverse transpose where it is invertible;
  // where it flattens the mesh into a plane (a scale of 0 along one axis) the surface is that
  // plane, whose normals the flattened triangles give; a point or a line (scale 0, the usual
  // way to hide a node) has no surface at all.
  struct NormalTransform {
    glm::dmat3 matrix{1.0};  // rank 3: the inverse transpose
    bool mirrored = false;   // rank 3: the transform turns the winding inside out
    int rank = 3;            // 3, 2 (a plane) or 1 (a line or a point)
  };
  static NormalTransform normal_transform(const glm::dmat3& m) {
    constexpr double kFlat = 1e-12;  // far below float positions' precision
    double big = 0.0;
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) big = std::max(big, std::abs(m[c][k]));
    if (!(big > 0.0)) return {glm::dmat3(0.0), false, 1};
    const glm::dmat3 a = m / big;  // the rank tests on a matrix of size 1, whatever the scale
    if (std::abs(glm::determinant(a)) > kFlat)
      return {glm::inverseTranspose(m), glm::determinant(m) < 0.0, 3};
    const glm::dmat3 minors(glm::cross(a[1], a[2]), glm::cross(a[2], a[0]), glm::cross(a[0], a[1]));
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k)
        if (std::abs(minors[c][k]) > kFlat) return {glm::dmat3(0.0), false, 2};
    return {glm::dmat3(0.0), false, 1};
  }

  // The world transform of `node` through its parents: a joint's, wherever the traversal
  // meets the mesh it moves.
  glm::dmat4 world_of(int node, int depth = 0) {
    if (const auto& known = world_[size_t(node)]) return *known;  // once per node, however many joints
    const std::string where = "nodes[" + std::to_string(node) + "]";
    if (depth > kMaxNodeDepth) throw InputError(file_, where, "node hierarchy is too deep, or a cycle");
    const glm::dmat4 local = local_transform(model_.nodes[size_t(node)], where);
    const int parent = parents_[size_t(node)];
    const glm::dmat4 world = parent < 0 ? local : world_of(parent, depth + 1) * local;
    world_[size_t(node)] = world;
    return world;
  }

  // Each joint's skinning matrix: its world transform times its inverse bind matrix.
  const std::vector<glm::dmat4>& joint_matrices(int skin_index, const std::string& node_where) {
    if (skin_index >= static_cast<int>(model_.skins.size()))
      throw InputError(file_, node_where + ".skin", "skin " + std::to_string(skin_index) + " does not exist");
    // Once per skin, however many nodes (instances) it skins.
    if (const auto it = skins_.find(skin_index); it != skins_.end()) return it->second;
    const tinygltf::Skin& skin = model_.skins[size_t(skin_index)];
    const std::string sw = "skins[" + std::to_string(skin_index) + "]";
    if (skin.joints.empty()) throw InputError(file_, sw + ".joints", "a skin needs at least one joint");
    std::vector<glm::dmat4> out(skin.joints.size(), glm::dmat4(1.0));
    if (skin.inverseBindMatrices >= 0) {
      const std::string iw = sw + ".inverseBindMatrices";
      const View v = view_of(skin.inverseBindMatrices, iw);
      if (v.components != 16 || v.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT || v.count < out.size())
        throw InputError(file_, iw, "must be MAT4 of FLOAT with one matrix per joint (" +
                                        std::to_string(out.size()) + ")");
      for (size_t j = 0; j < out.size(); ++j)
        for (int k = 0; k < 16; ++k) {
          const float x = component(v, j, k);
          if (!std::isfinite(x)) throw InputError(file_, iw + "[" + std::to_string(j) + "]", "value is not finite");
          out[j][k / 4][k % 4] = x;  // column-major, as glm
        }
      for (size_t j = 0; j < out.size(); ++j) make_affine(out[j], iw + "[" + std::to_string(j) + "]");
    }
    for (size_t j = 0; j < out.size(); ++j) {
      const int joint = skin.joints[j];
      if (joint < 0 || joint >= static_cast<int>(model_.nodes.size()))
        throw InputError(file_, sw + ".joints[" + std::to_string(j) + "]",
                         "node " + std::to_string(joint) + " does not exist");
      out[j] = world_of(joint) * out[j];
      for (int c = 0; c < 4; ++c)
        for (int k = 0; k < 4; ++k)
          if (!std::isfinite(out[j][c][k]))
            throw InputError(file_, sw + ".joints[" + std::to_string(j) + "]", "joint transform is not finite");
    }
    return skins_[skin_index] = std::move(out);
  }

  // The morph weights a node's mesh is drawn with: the node's own, else the mesh's defaults,
  // else none (every target at weight 0). Field named for the messages.
  std::pair<std::vector<double>, std::string> morph_weights(const tinygltf::Node& n, const std::string& nw,
                                                            const tinygltf::Mesh& mesh, const std::string& mw) const {
    std::pair<std::vector<double>, std::string> w =
        n.weights.empty() ? std::pair{mesh.weights, mw + ".weights"} : std::pair{n.weights, nw + ".weights"};
    for (size_t k = 0; k < w.first.size(); ++k)
      if (!std::isfinite(w.first[k]))
        throw InputError(file_, w.second + "[" + std::to_string(k) + "]", "weight is not finite");
    return w;
  }

  // Morph targets and skins move `values` more vertex values (a target's attribute, a skin set's
  // four joints): bounded like the triangles that must be read, or a small file of many targets
  // sharing one accessor (or a deep skin instanced many times) would run for hours.
  void charge(uint64_t values, const std::string& field) {
    const uint64_t limit = sat_mul(budget_.max_faces, 3);
    deformed_ = sat_add(deformed_, values);
    if (deformed_ > limit)
      throw InputError(file_, field,
                       "morph targets and skins move " + std::to_string(deformed_) +
                           " vertex values or more, more than the budget of " + std::to_string(limit) + " (3 x " +
                           kMaxFacesFlag + "; raise it with " + kMaxFacesFlag + ")");
  }

  // Adds a primitive's weighted morph target deltas of `attribute` (POSITION or NORMAL) to `v`.
  void add_morph(const tinygltf::Primitive& prim, const std::string& pw,
                 const std::pair<std::vector<double>, std::string>& weights, const char* attribute,
                 std::vector<glm::vec3>& v) {
    if (weights.first.empty()) return;
    if (prim.targets.size() != weights.first.size())
      throw InputError(file_, weights.second,
                       std::to_string(weights.first.size()) + " weights for the " + std::to_string(prim.targets.size()) +
                           " morph targets of " + pw);
    for (size_t t = 0; t < prim.targets.size(); ++t) {
      const double w = weights.first[t];
      const auto it = prim.targets[t].find(attribute);
      if (w == 0.0 || it == prim.targets[t].end()) continue;
      const std::string tw = pw + ".targets[" + std::to_string(t) + "]." + attribute;
      const View dv = view_of(it->second, tw);
      if (dv.components != 3 || dv.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT || dv.count != v.size())
        throw InputError(file_, tw, "must be VEC3 of FLOAT with one value per position");
      charge(v.size(), tw);
      for (size_t i = 0; i < v.size(); ++i) {
        const glm::dvec3 d(component(dv, i, 0), component(dv, i, 1), component(dv, i, 2));
        if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z))
          throw InputError(file_, tw + "[" + std::to_string(i) + "]", "value is not finite");
        v[i] = glm::vec3(glm::dvec3(v[i]) + w * d);
      }
    }
  }

  // A skinned primitive's JOINTS_n / WEIGHTS_n sets (every set it has), checked once.
  struct SkinSet {
    View joints, weights;
    std::string joints_where, weights_where;
  };
  std::vector<SkinSet> skin_sets(const tinygltf::Primitive& prim, const std::string& pw, size_t count) const {
    std::vector<SkinSet> sets;
    for (int k = 0;; ++k) {
      const auto ji = prim.attributes.find("JOINTS_" + std::to_string(k));
      const auto wi = prim.attributes.find("WEIGHTS_" + std::to_string(k));
      if (ji == prim.attributes.end() && wi == prim.attributes.end()) break;
      const std::string jw = pw + ".attributes.JOINTS_" + std::to_string(k);
      const std::string ww = pw + ".attributes.WEIGHTS_" + std::to_string(k);
      if (ji == prim.attributes.end()) throw InputError(file_, ww, "has no JOINTS_" + std::to_string(k));
      if (wi == prim.attributes.end()) throw InputError(file_, jw, "has no WEIGHTS_" + std::to_string(k));
      SkinSet set{view_of(ji->second, jw), view_of(wi->second, ww), jw, ww};
      const View& jv = set.joints;
      const View& wv = set.weights;
      if (jv.components != 4 || jv.count != count ||
          (jv.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
           jv.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT))
        throw InputError(file_, jw, "must be VEC4 of UNSIGNED_BYTE or UNSIGNED_SHORT with one entry per position");
      if (wv.components != 4 || wv.count != count ||
          !(wv.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT ||
            (wv.normalized && (wv.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                               wv.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT))))
        throw InputError(file_, ww,
                         "must be VEC4 of FLOAT (or normalized UNSIGNED_BYTE/SHORT) with one entry per position");
      sets.push_back(std::move(set));
    }
    if (sets.empty()) throw InputError(file_, pw + ".attributes", "a skinned mesh needs JOINTS_0 and WEIGHTS_0");
    return sets;
  }

  // Vertex i's blend of its joints' matrices, its weights normalised to sum 1.
  glm::dmat4 skin_matrix(const std::vector<SkinSet>& sets, const std::vector<glm::dmat4>& joints, size_t i) const {
    glm::dmat4 out(0.0);
    double total = 0.0;
    for (const SkinSet& set : sets)
      for (int k = 0; k < 4; ++k) {
        const double w = component(set.weights, i, k);
        if (!(w >= 0.0) || !std::isfinite(w))
          throw InputError(file_, set.weights_where + "[" + std::to_string(i) + "]",
                           "a joint weight must be finite and >= 0");
        if (w == 0.0) continue;
        const uint32_t j = index_at(set.joints, i, k);
        if (j >= joints.size())
          throw InputError(file_, set.joints_where + "[" + std::to_string(i) + "]",
                           "joint " + std::to_string(j) + " out of range (the skin has " +
                               std::to_string(joints.size()) + ")");
        out += w * joints[j];
        total += w;
      }
    if (!(total > 0.0))
      throw InputError(file_, sets[0].weights_where + "[" + std::to_string(i) + "]",
                       "the vertex has no joint weight, so no joint places it");
    return out / total;
  }

  void add_mesh(int node, const glm::dmat4& world) {
    const tinygltf::Node& n = model_.nodes[size_t(node)];
    const std::string nw = "nodes[" + std::to_string(node) + "]";
    const int mesh_index = n.mesh;
    const std::string mw = "meshes[" + std::to_string(mesh_index) + "]";
    if (mesh_index >= static_cast<int>(model_.meshes.size()))
      throw InputError(file_, mw, "mesh does not exist");
    const tinygltf::Mesh& mesh = model_.meshes[size_t(mesh_index)];
    const auto weights = morph_weights(n, nw, mesh, mw);
    // A skinned mesh is placed by its joints alone: the specification has the node's own
    // transform ignored. The joints stand as the file poses them (pelt plays no animation).
    static const std::vector<glm::dmat4> kNoJoints;
    const std::vector<glm::dmat4>& joints = n.skin >= 0 ? joint_matrices(n.skin, nw) : kNoJoints;
    const NormalTransform whole = normal_transform(glm::dmat3(world));
    if (joints.empty() && whole.rank < 2) {
      // A node scaled to nothing (how files hide one): no triangle to draw, and its vertices
      // would still count in the mesh's bounds and uv area, which size the fur. Its triangles
      // still count in --max-faces (counted before any transform).
      hidden_.push_back(nw);
      return;
    }
    const auto& prims = mesh.primitives;
    for (size_t pi = 0; pi < prims.size(); ++pi) {
      const tinygltf::Primitive& prim = prims[pi];
      const std::string pw = mw + ".primitives[" + std::to_string(pi) + "]";
      // tinygltf gives a primitive without `mode` TINYGLTF_MODE_TRIANGLES.
      if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
          prim.mode != TINYGLTF_MODE_TRIANGLE_FAN)
        throw InputError(file_, pw + ".mode", "only triangles, strips and fans are supported, got mode " +
                                                  std::to_string(prim.mode));
      if (prim.material >= static_cast<int>(model_.materials.size()))
        throw InputError(file_, pw + ".material", "material " + std::to_string(prim.material) + " does not exist");
      const UvSet uv_set = uv_set_of(prim.material);
      const auto pos_it = prim.attributes.find("POSITION");
      if (pos_it == prim.attributes.end()) throw InputError(file_, pw, "has no POSITION attribute");
      const std::string posw = pw + ".attributes.POSITION";
      const View pos = view_of(pos_it->second, posw);
      if (pos.components != 3 || pos.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT)
        throw InputError(file_, posw, "must be VEC3 of FLOAT");

      // The file's values (floats) before the transform: morphs add to them.
      std::vector<glm::vec3> local(pos.count);
      for (size_t i = 0; i < pos.count; ++i) {
        const glm::vec3 p(component(pos, i, 0), component(pos, i, 1), component(pos, i, 2));
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
          throw InputError(file_, posw + "[" + std::to_string(i) + "]",
                           std::string("position is ") + (std::isnan(p.x + p.y + p.z) ? "NaN" : "infinite"));
        local[i] = p;
      }
      add_morph(prim, pw, weights, "POSITION", local);
      // A flattened transform (rank 2) takes its normals from the flattened faces.
      std::vector<glm::vec3> normals;
      if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end() && (!joints.empty() || whole.rank == 3)) {
        const std::string nw2 = pw + ".attributes.NORMAL";
        const View nv = view_of(it->second, nw2);
        if (nv.components != 3 || nv.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT || nv.count != pos.count)
          throw InputError(file_, nw2, "must be VEC3 of FLOAT with one normal per position");
        normals.resize(nv.count);
        for (size_t i = 0; i < nv.count; ++i) {
          normals[i] = glm::vec3(component(nv, i, 0), component(nv, i, 1), component(nv, i, 2));
          if (!std::isfinite(normals[i].x) || !std::isfinite(normals[i].y) || !std::isfinite(normals[i].z))
            throw InputError(file_, nw2 + "[" + std::to_string(i) + "]", "normal is not finite");
        }
        add_morph(prim, pw, weights, "NORMAL", normals);
      }

      Mesh& m = out_.mesh;
      const auto base = static_cast<uint32_t>(m.positions.size());
      const std::vector<SkinSet> sets = joints.empty() ? std::vector<SkinSet>{} : skin_sets(prim, pw, pos.count);
      if (!sets.empty()) charge(sat_mul(pos.count, 4 * sets.size()), pw + ".attributes.JOINTS_0");
      std::vector<uint8_t> vertex_mirrored(sets.empty() ? 0 : pos.count);  // a skinned vertex's joints mirror it
      for (size_t i = 0; i < pos.count; ++i) {
        const glm::dmat4 to_world = sets.empty() ? world : skin_matrix(sets, joints, i);
        const glm::dvec4 p = to_world * glm::dvec4(glm::dvec3(local[i]), 1.0);
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
          throw InputError(file_, posw + "[" + std::to_string(i) + "]", "the transformed position is not finite");
        m.positions.emplace_back(glm::dvec3(p));
        if (sets.empty()) {
          if (!normals.empty()) m.normals.emplace_back(whole.matrix * glm::dvec3(normals[i]));
          continue;
        }
        const NormalTransform t = normal_transform(glm::dmat3(to_world));
        vertex_mirrored[i] = t.mirrored;
        // A vertex its joints collapse has no surface of its own: any unit normal will do, and
        // a zero one would have every normal of the file recomputed.
        if (!normals.empty())
          m.normals.emplace_back(t.rank == 3 ? glm::vec3(t.matrix * glm::dvec3(normals[i])) : glm::vec3(0.0f, 1.0f, 0.0f));
      }
      const bool flat = m.normals.size() != m.positions.size();

      const std::string uv_name = "TEXCOORD_" + std::to_string(uv_set.index);
      bool has_uvs = true;
      if (auto it = prim.attributes.find(uv_name); it != prim.attributes.end()) {
        const std::string tw = pw + ".attributes." + uv_name;
        const View tv = view_of(it->second, tw);
        const bool ok_type = tv.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT ||
                             (tv.normalized && (tv.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                                tv.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT));
        if (tv.components != 2 || !ok_type || tv.count != pos.count)
          throw InputError(file_, tw, "must be VEC2 of FLOAT (or normalized UNSIGNED_BYTE/SHORT) with one uv per position");
        for (size_t i = 0; i < tv.count; ++i) {
          const glm::vec2 t(component(tv, i, 0), component(tv, i, 1));
          if (!std::isfinite(t.x) || !std::isfinite(t.y))
            throw InputError(file_, tw + "[" + std::to_string(i) + "]", "uv is not finite");
          m.uvs.push_back(t);
        }
      } else if (uv_set.index != 0) {
        // TEXCOORD_0 in its place would put the map where the file does not: refused.
        throw InputError(file_, uv_set.where, "names " + uv_name + ", which " + pw + " does not have");
      } else {
        has_uvs = false;
        m.uvs.resize(m.positions.size(), glm::vec2(0.0f));
        note_uvless(uvless_, pw);  // once, though a mesh drawn by several nodes is read once per node
      }

      std::vector<uint32_t> idx;
      if (prim.indices >= 0) {
        const std::string iw = pw + ".indices";
        const View iv = view_of(prim.indices, iw);
        if (iv.components != 1 || (iv.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                                   iv.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                                   iv.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
          throw InputError(file_, iw, "must be SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
        idx.resize(iv.count);
        for (size_t i = 0; i < iv.count; ++i) {
          idx[i] = index_at(iv, i);
          if (idx[i] >= pos.count)
            throw InputError(file_, iw + "[" + std::to_string(i) + "]",
                             "index " + std::to_string(idx[i]) + " out of range (" +
                                 std::to_string(pos.count) + " vertices)");
        }
      } else {
        idx.resize(pos.count);
        for (size_t i = 0; i < pos.count; ++i) idx[i] = static_cast<uint32_t>(i);
      }
      check_index_count(prim.mode, idx.size(), prim.indices >= 0 ? prim.indices : pos_it->second,
                        prim.indices >= 0);
      const size_t first_index = m.indices.size();
      // A skinned triangle turns inside out where most of its corners' joints mirror it.
      const auto mirrored = [&](uint32_t a, uint32_t b, uint32_t c) {
        if (sets.empty()) return whole.mirrored;
        return vertex_mirrored[a] + vertex_mirrored[b] + vertex_mirrored[c] >= 2;
      };
      append_triangles(prim.mode, idx, base, mirrored);
      if (flat) make_flat(base, first_index);
      uv_missing_.resize(m.positions.size(), uint8_t{!has_uvs});
      if (const size_t added = (m.indices.size() - first_index) / 3; added > 0) {
        triangle_maps_.insert(triangle_maps_.end(), added, maps_of(prim.material));
        if (prim.material < 0) {
          if (unmaterialed_.empty()) unmaterialed_ = pw;
          unmaterialed_triangles_ += added;
        }
      }
    }
  }

  // A primitive without NORMAL: the specification asks for flat normals (3.7.2.1), so each
  // triangle gets corners of its own with its face's normal (after the winding the node's
  // transform gave it). A zero-area triangle, which has no normal and covers no pixel, gets +y.
  void make_flat(uint32_t base, size_t first_index) {
    Mesh& m = out_.mesh;
    const std::vector<glm::vec3> positions(m.positions.begin() + base, m.positions.end());
    const std::vector<glm::vec2> uvs(m.uvs.begin() + base, m.uvs.end());
    m.positions.resize(base);
    m.uvs.resize(base);
    m.normals.resize(base);
    for (size_t t = first_index; t + 2 < m.indices.size(); t += 3) {
      uint32_t* corner = &m.indices[t];
      const glm::dvec3 a(positions[corner[0] - base]), b(positions[corner[1] - base]), c(positions[corner[2] - base]);
      const glm::dvec3 n = glm::cross(b - a, c - a);
      const double len = glm::length(n);
      const glm::vec3 normal = len > 0.0 && std::isfinite(len) ? glm::vec3(n / len) : glm::vec3(0.0f, 1.0f, 0.0f);
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = corner[k] - base;
        corner[k] = static_cast<uint32_t>(m.positions.size());
        m.positions.push_back(positions[v]);
        m.uvs.push_back(uvs[v]);
        m.normals.push_back(normal);
      }
    }
  }

  // append_triangles makes a triangle of every 3 indices of a list and of each index past the
  // second of a strip or fan; indices left over would be dropped without a word.
  void check_index_count(int mode, size_t count, int accessor, bool indexed) const {
    const std::string what = indexed ? " indices" : " positions (the primitive has no indices)";
    const std::string field = "accessors[" + std::to_string(accessor) + "].count";
    if (mode == TINYGLTF_MODE_TRIANGLES && count % 3 != 0)
      throw InputError(file_, field, std::to_string(count) + what + " do not make whole triangles: a triangle list " +
                                         "takes a multiple of 3");
    if (mode != TINYGLTF_MODE_TRIANGLES && count > 0 && count < 3)
      throw InputError(file_, field, std::to_string(count) + what + " make no triangle: a " +
                                         (mode == TINYGLTF_MODE_TRIANGLE_STRIP ? "strip" : "fan") +
                                         " takes at least 3");
  }

  template <class Mirrored>
  void append_triangles(int mode, const std::vector<uint32_t>& idx, uint32_t base, const Mirrored& mirrored) {
    auto& out = out_.mesh.indices;
    const auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
      if (mirrored(a, b, c)) std::swap(b, c);  // a mirroring transform turns the winding inside out
      out.insert(out.end(), {base + a, base + b, base + c});
    };
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      for (size_t i = 2; i < idx.size(); ++i)
        (i % 2 == 0) ? emit(idx[i - 2], idx[i - 1], idx[i]) : emit(idx[i - 1], idx[i - 2], idx[i]);
    } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
      for (size_t i = 2; i < idx.size(); ++i) emit(idx[0], idx[i - 1], idx[i]);
    } else {
      for (size_t i = 0; i + 2 < idx.size(); i += 3) emit(idx[i], idx[i + 1], idx[i + 2]);
    }
  }

  // The TEXCOORD_n set a material's maps are drawn with (texCoord), and the texCoord field that
  // named it. pelt keeps one uv set per vertex, so a colour map and a normal map naming two
  // sets cannot both be drawn as the file says.
  struct UvSet {
    int index = 0;
    std::string where;
  };

  UvSet uv_set_of(int material) const {
    if (material < 0) return {};
    const tinygltf::Material& mat = model_.materials[size_t(material)];
    const std::string mw = "materials[" + std::to_string(material) + "]";
    const tinygltf::TextureInfo& color = mat.pbrMetallicRoughness.baseColorTexture;
    const tinygltf::NormalTextureInfo& normal = mat.normalTexture;
    const UvSet c = tex_coord_of(color, mw + ".pbrMetallicRoughness.baseColorTexture");
    const UvSet n = tex_coord_of(normal, mw + ".normalTexture");
    if (color.index >= 0 && normal.index >= 0 && c.index != n.index)
      throw InputError(file_, n.where,
                       "TEXCOORD_" + std::to_string(n.index) + " is not the baseColorTexture's TEXCOORD_" +
                           std::to_string(c.index) + ": pelt draws both maps with one uv set");
    if (color.index >= 0) return c;
    if (normal.index >= 0) return n;
    return {};
  }

  // KHR_texture_transform's object on a texture info, or null.
  template <class Info>
  static const tinygltf::Value* texture_transform(const Info& info) {
    const auto it = info.extensions.find("KHR_texture_transform");
    return it != info.extensions.end() && it->second.IsObject() ? &it->second : nullptr;
  }

  // A texture info's uv set: KHR_texture_transform's texCoord overrides the info's own.
  template <class Info>
  static UvSet tex_coord_of(const Info& info, const std::string& where) {
    if (const tinygltf::Value* t = texture_transform(info); t && t->Has("texCoord"))
      return {t->Get("texCoord").GetNumberAsInt(), where + ".extensions.KHR_texture_transform.texCoord"};
    return {info.texCoord, where + ".texCoord"};
  }

  // Where a texture info's map lies: its sampler's wrapS and wrapT, and KHR_texture_transform's
  // offset, rotation and scale as the extension composes them (translation * rotation * scale,
  // the rotation counter-clockwise in uv, v down). check_fields_as_written has checked the values.
  template <class Info>
  MapPlacement placement_of(const Info& info) const {
    MapPlacement p;
    const int texture = info.index;
    if (texture >= 0 && size_t(texture) < model_.textures.size()) {
      const int sampler = model_.textures[size_t(texture)].sampler;
      if (sampler >= 0 && size_t(sampler) < model_.samplers.size()) {
        const auto wrap = [](int mode) {
          return mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE     ? raster::Wrap::Clamp
                 : mode == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT ? raster::Wrap::Mirror
                                                                 : raster::Wrap::Repeat;
        };
        p.wrap_u = wrap(model_.samplers[size_t(sampler)].wrapS);
        p.wrap_v = wrap(model_.samplers[size_t(sampler)].wrapT);
      }
    }
    if (const tinygltf::Value* t = texture_transform(info)) {
      const auto pair = [&](const char* key, double fallback, int i) {
        return t->Has(key) ? t->Get(key).Get(i).GetNumberAsDouble() : fallback;
      };
      const double r = t->Has("rotation") ? t->Get("rotation").GetNumberAsDouble() : 0.0;
      const double sx = pair("scale", 1.0, 0), sy = pair("scale", 1.0, 1);
      const double c = std::cos(r), sn = std::sin(r);
      p.m = {float(sx * c), float(sy * sn), float(pair("offset", 0.0, 0)),
             float(-sx * sn), float(sy * c), float(pair("offset", 0.0, 1))};
    }
    return p;
  }

  // The map set of a primitive's material (-1: none) in sets_, added at its first use: a
  // material's maps and alpha, read once, and shared with an earlier material that draws alike
  // (add_map_set; an embedded image is decoded once, so two materials naming it share pixels).
  uint32_t maps_of(int material) {
    if (const auto it = set_of_material_.find(material); it != set_of_material_.end()) return it->second;
    MeshMaps maps;
    maps.material = kNoMaterial;
    if (material >= 0 && material < static_cast<int>(model_.materials.size())) {
      const tinygltf::Material& mat = model_.materials[size_t(material)];
      const std::string mw = "materials[" + std::to_string(material) + "]";
      note_undrawn(mat, mw);
      maps.material = mat.name.empty() ? mw : mat.name;
      const tinygltf::TextureInfo& color = mat.pbrMetallicRoughness.baseColorTexture;
      if (color.index >= 0) {
        resolve_texture(color.index, ColorEncoding::srgb, mw + ".pbrMetallicRoughness.baseColorTexture",
                        maps.color_map);
        maps.color_map.placement = placement_of(color);
      }
      if (mat.normalTexture.index >= 0) {
        resolve_texture(mat.normalTexture.index, ColorEncoding::linear, mw + ".normalTexture", maps.normal_map);
        maps.normal_map.placement = placement_of(mat.normalTexture);
      }
      // check_fields_as_written has checked the mode's word, the cutoff and the factor.
      if (mat.alphaMode == "MASK" || mat.alphaMode == "BLEND") {
        const std::vector<double>& f = mat.pbrMetallicRoughness.baseColorFactor;
        maps.alpha_mode = mat.alphaMode == "MASK" ? AlphaMode::mask : AlphaMode::blend;
        if (maps.alpha_mode == AlphaMode::mask) maps.alpha_cutoff = float(mat.alphaCutoff) + 0.0f;  // -0 reads 0
        maps.alpha_factor = f.size() == 4 ? float(f[3]) : 1.0f;
      }
    }
    return set_of_material_[material] = add_map_set(sets_, std::move(maps));
  }

  // What a drawn primitive's material asks for that pelt does not draw (the scene's material
  // decides colour and shading; a mesh file gives maps and alpha): said once per material, so
  // that a tint not applied is no surprise. Until 2026-11-27 alphaMode MASK and BLEND were
  // warned of and drawn opaque.
  void note_undrawn(const tinygltf::Material& mat, const std::string& mw) {
    const std::vector<double>& f = mat.pbrMetallicRoughness.baseColorFactor;
    // The factor's alpha is drawn (MASK, BLEND) or means nothing (OPAQUE).
    if (f.size() == 4 && (f[0] != 1.0 || f[1] != 1.0 || f[2] != 1.0)) {
      char factor[128];
      std::snprintf(factor, sizeof factor, "[%g, %g, %g, %g]", f[0], f[1], f[2], f[3]);
      out_.warnings.push_back(mw + ".pbrMetallicRoughness.baseColorFactor " + factor +
                              " is not applied to the colour: the scene's material colour is the albedo (times the "
                              "map)");
    }
    // The emissive texture is multiplied by the factor, [0, 0, 0] unless given: light only with a factor.
    const std::vector<double>& e = mat.emissiveFactor;
    if (std::any_of(e.begin(), e.end(), [](double x) { return x != 0.0; }))
      out_.warnings.push_back(mw + " emits light (emissiveFactor" +
                              (mat.emissiveTexture.index >= 0 ? std::string(", emissiveTexture") : std::string()) +
                              "), which pelt does not draw");
  }

  int image_source(int texture, const std::string& where) const {
    if (texture >= static_cast<int>(model_.textures.size()))
      throw InputError(file_, where, "texture " + std::to_string(texture) + " does not exist");
    const int source = model_.textures[texture].source;
    if (source < 0 || source >= static_cast<int>(model_.images.size()))
      throw InputError(file_, where, "texture has no valid image source");
    return source;
  }

  void resolve_texture(int texture, ColorEncoding encoding, const std::string& where, TextureRef& ref) {
    if (texture < 0) return;
    const int source = image_source(texture, where);
    const tinygltf::Image& img = model_.images[source];
    if (!img.uri.empty() && img.uri.rfind("data:", 0) != 0) {
      ref.path = dir_ / decode_uri(img.uri);
      return;
    }
    std::shared_ptr<const ImageRGBA>& decoded = decoded_[{source, encoding}];
    if (!decoded) {
      auto pixels = std::make_shared<ImageRGBA>(
          pixels_to_rgba(img.image.data(), img.width, img.height, img.component, img.bits, encoding));
      if (pixels->empty())
        throw InputError(file_, "images[" + std::to_string(source) + "]", "embedded image could not be decoded");
      decoded = std::move(pixels);
    }
    ref.pixels = decoded;
  }

  static std::string decode_uri(const std::string& uri) {
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
      if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
          std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
        out.push_back(static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16)));
        i += 2;
      } else {
        out.push_back(uri[i]);
      }
    }
    return out;
  }

  const tinygltf::Model& model_;
  std::string file_;
  std::filesystem::path dir_;
  LoadedMesh out_;
  const Budget& budget_;
  std::vector<int> parents_;                       // each node's first parent, -1 for none
  std::vector<std::optional<glm::dmat4>> world_;   // world_of's, per node
  std::map<int, std::vector<glm::dmat4>> skins_;   // joint_matrices', per skin
  std::vector<std::string> hidden_;                // nodes scaled to a point or a line
  uint64_t deformed_ = 0;                          // vertex values moved by morphs and skins
  std::vector<uint8_t> uv_missing_;  // per vertex (settle_uvs)
  std::vector<std::string> uvless_;  // the first primitives without uvs (note_uvless)
  std::vector<MeshMaps> sets_;                 // maps_of's, in the order of their first primitive
  std::string unmaterialed_;                   // the first drawn primitive without a material
  uint64_t unmaterialed_triangles_ = 0;        // and the triangles of all such primitives
  std::vector<uint32_t> triangle_maps_;        // each triangle's set in sets_
  std::map<int, uint32_t> set_of_material_;    // by material index (-1: none)
  // Embedded images decoded, by image index and encoding: shared by the sets that use them.
  std::map<std::pair<int, ColorEncoding>, std::shared_ptr<const ImageRGBA>> decoded_;
};

std::string trim(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ')) s.pop_back();
  return s;
}

// What the image callback needs besides tinygltf's arguments, and what it found.
struct ImageCheck {
  const tinygltf::Model* model;
  const Budget* budget;
  std::optional<InputError> refused;  // set when an image is over budget or not PNG/JPEG
};

// Image decoding through tinygltf, after checking what tinygltf 2.7 does not: that an
// image's bufferView lies inside its buffer (it hands stb_image a pointer past the end
// otherwise, a heap overflow found by fuzzing), and that the image's header, read before
// stb_image allocates its pixels, is within the texture budget. glTF 2.0 allows PNG and
// JPEG images only; anything else is refused here rather than handed to stb_image, whose
// other formats' sizes we do not read.
bool load_image_checked(tinygltf::Image* image, const int image_idx, std::string* err,
                        std::string* warn, int req_width, int req_height, const unsigned char* bytes,
                        int size, void* user) {
  auto* check = static_cast<ImageCheck*>(user);
  const tinygltf::Model* model = check->model;
  // tinygltf calls this while parsing images[image_idx]: `image` is that image, not yet in
  // model->images; buffers and bufferViews are already parsed.
  {
    const int view = image->bufferView;
    if (view >= 0) {
      const bool view_ok = size_t(view) < model->bufferViews.size();
      const tinygltf::BufferView* bv = view_ok ? &model->bufferViews[size_t(view)] : nullptr;
      const bool buffer_ok = bv && bv->buffer >= 0 && size_t(bv->buffer) < model->buffers.size();
      if (!buffer_ok || bv->byteOffset > model->buffers[size_t(bv->buffer)].data.size() ||
          bv->byteLength > model->buffers[size_t(bv->buffer)].data.size() - bv->byteOffset) {
        if (err)
          *err = "images[" + std::to_string(image_idx) + "]: bufferView " + std::to_string(view) +
                 " runs past the end of its buffer";
        return false;
      }
    }
  }
  const std::string where = "images[" + std::to_string(image_idx) + "]";
  const auto dims = encoded_image_size(bytes, size > 0 ? size_t(size) : 0);
  if (!dims) {
    check->refused.emplace("", where, "not a PNG or JPEG image with a readable size (glTF 2.0 images are PNG or JPEG)");
  } else if (dims->width > check->budget->max_texture_side || dims->height > check->budget->max_texture_side) {
    check->refused.emplace("", where,
                           texture_side_refusal(dims->width, dims->height, check->budget->max_texture_side));
  }
  if (check->refused) {
    if (err) *err = where + ": " + check->refused->reason;
    return false;
  }
  return tinygltf::LoadImageData(image, image_idx, err, warn, req_width, req_height, bytes, size, nullptr);
}

// tinygltf's reads of the files a glTF names (its buffers' and images' uris), checked first: a
// folder's "size" made tinygltf allocate 2^63 bytes (std::bad_alloc, exit 1) and a pipe or a
// device blocked the set-up for ever. A file larger than the whole memory budget is refused
// unread. A missing file is left to tinygltf, whose message names the uri's image or buffer.
bool read_named_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  auto* check = static_cast<ImageCheck*>(user);
  const std::string reason = unreadable_file_reason(path);
  std::error_code ec;
  if (reason.empty()) {
    if (const uintmax_t size = std::filesystem::file_size(path, ec); !ec && size > check->budget->max_memory_bytes)
      check->refused.emplace("", "", "`" + path + "`, which it names, is " + describe_bytes(size) + ", " +
                                         over_budget(describe_bytes(check->budget->max_memory_bytes), kMaxMemoryFlag));
  } else if (reason != kFileNotFound) {
    check->refused.emplace("", "", "`" + path + "`, which it names, " + reason);
  }
  if (check->refused) {
    if (err) *err += check->refused->reason + "\n";
    return false;
  }
  return tinygltf::ReadWholeFile(out, err, path, nullptr);
}

// Whether a uri's file exists, without opening it: tinygltf's own test opens it, which blocks on a
// pipe until something writes to it.
bool named_file_exists(const std::string& path, void*) {
  std::error_code ec;
  return std::filesystem::exists(path, ec);
}

uint32_t little_endian_u32(const unsigned char* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

// tinygltf reads a GLB of any header version as glTF 2.0's layout; version 1 (KHR_binary_glTF)
// is laid out otherwise and holds glTF 1.0 JSON.
void check_glb_version(const std::filesystem::path& path, const std::string& file) {
  std::ifstream in(path, std::ios::binary);
  unsigned char header[12];
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  // Without the magic and the file's own length after the version, the bytes are no GLB
  // header to read a version from: tinygltf names what is wrong.
  if (!in.read(reinterpret_cast<char*>(header), sizeof header) || std::memcmp(header, "glTF", 4) != 0 || ec ||
      little_endian_u32(header + 8) != size)
    return;
  const uint32_t version = little_endian_u32(header + 4);
  if (version != 2)
    throw InputError(file, "header.version", "GLB version " + std::to_string(version) +
                                                 ": pelt reads glTF 2.0 binaries (version 2)");
}

// The JSON tinygltf has just read without error: the .gltf file, or a GLB's first chunk.
std::string gltf_json_text(const std::filesystem::path& path, bool binary) {
  std::ifstream in(path, std::ios::binary);
  if (!binary) return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  unsigned char header[20];
  if (!in.read(reinterpret_cast<char*>(header), sizeof header)) return {};
  // The chunk's length is the file's word: no more than the file holds is allocated for it.
  std::error_code ec;
  const uint64_t size = std::filesystem::file_size(path, ec);
  const uint32_t length = little_endian_u32(header + 12);
  if (ec || length > size - std::min<uint64_t>(size, sizeof header)) return {};
  std::string text(length, '\0');
  if (!in.read(text.data(), std::streamsize(text.size()))) return {};
  return text;
}

// tinygltf reads an optional integer it cannot take (a negative one where it wants an unsigned
// one, a fraction, a string) as absent, keeps -1 where -1 means absent, and truncates one past
// int's range: `"byteOffset": -4` was read from offset 0, `"mode": -1` drawn as triangles,
// `"material": -1` as none, `"material": 4294967296` as material 0. An index list (a node's
// children, a scene's nodes) it reads up to its first element it cannot take, dropping the rest,
// wraps the elements past int's range, and ignores a list that is no array; a primitive's
// attributes it wraps the same way. So the integers pelt reads are checked in the file's own
// JSON: each, where given, an integer in [0, its largest].
void check_fields_as_written(const std::string& text, const std::string& file) {
  const nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
  constexpr uint64_t kIndex = INT_MAX;    // tinygltf keeps indices in an int
  constexpr uint64_t kSize = UINT64_MAX;  // and offsets in a size_t
  const auto integer = [&](const nlohmann::json& v, const std::string& field, uint64_t most) {
    if (!v.is_number_integer())
      throw InputError(file, field, "expected an integer, got " + (v.is_number() ? v.dump() : json_type_name(v)));
    if (!v.is_number_unsigned() || v.get<uint64_t>() > most)
      throw InputError(file, field, (most == kSize ? std::string("must not be negative") :
                                                     "must be in [0, " + std::to_string(most) + "]") +
                                        ", got " + v.dump());
  };
  const auto check = [&](const nlohmann::json& obj, const std::string& path, const char* key, uint64_t most) {
    if (!obj.is_object()) return;  // a misshapen object is tinygltf's to refuse
    const auto it = obj.find(key);
    if (it != obj.end()) integer(*it, json_child(path, key), most);
  };
  const auto check_indices = [&](const nlohmann::json& obj, const std::string& path, const char* key) {
    if (!obj.is_object()) return;
    const auto it = obj.find(key);
    if (it == obj.end()) return;
    const std::string field = json_child(path, key);
    if (!it->is_array()) throw InputError(file, field, "expected an array of indices, got " + json_type_name(*it));
    for (size_t i = 0; i < it->size(); ++i) integer((*it)[i], json_index(field, i), kIndex);
  };
  const auto each = [&](const nlohmann::json& obj, const std::string& path, const char* key, const auto& fn) {
    if (!obj.is_object()) return;
    const auto it = obj.find(key);
    if (it == obj.end() || !it->is_array()) return;
    for (size_t i = 0; i < it->size(); ++i) fn((*it)[i], json_index(json_child(path, key), i));
  };
  const auto number = [&](const nlohmann::json& v, const std::string& field) {
    if (!v.is_number()) throw InputError(file, field, "expected a number, got " + json_type_name(v));
    if (std::abs(v.get<double>()) > kMostMapValue)
      throw InputError(file, field, v.dump() + " is too large (above 1e30)");
  };
  const auto numbers = [&](const nlohmann::json& obj, const std::string& path, const char* key) {
    const auto it = obj.find(key);
    if (it == obj.end()) return;
    const std::string field = json_child(path, key);
    if (!it->is_array() || it->size() != 2)
      throw InputError(file, field, "expected an array of 2 numbers, got " + json_type_name(*it));
    for (size_t i = 0; i < 2; ++i) number((*it)[i], json_index(field, i));
  };
  // KHR_texture_transform (its specification): offset [2], rotation (radians), scale [2], and
  // a texCoord that overrides the texture info's. tinygltf keeps them as untyped values.
  const auto texture_transform = [&](const nlohmann::json& info, const std::string& path) {
    if (!info.contains("extensions") || !info["extensions"].is_object()) return;
    const auto it = info["extensions"].find("KHR_texture_transform");
    if (it == info["extensions"].end()) return;
    const std::string field = json_child(json_child(path, "extensions"), "KHR_texture_transform");
    if (!it->is_object()) throw InputError(file, field, "expected an object, got " + json_type_name(*it));
    numbers(*it, field, "offset");
    numbers(*it, field, "scale");
    if (it->contains("scale"))
      for (size_t i = 0; i < 2; ++i)
        if (std::abs((*it)["scale"][i].template get<double>()) < kLeastMapScale)
          throw InputError(file, json_index(json_child(field, "scale"), i), tiny_scale_reason((*it)["scale"][i].dump()));
    if (it->contains("rotation")) number((*it)["rotation"], json_child(field, "rotation"));
    check(*it, field, "texCoord", kIndex);
  };
  const auto texture_info = [&](const nlohmann::json& obj, const std::string& path, const char* key) {
    if (!obj.is_object() || !obj.contains(key)) return;
    check(obj[key], json_child(path, key), "index", kIndex);
    check(obj[key], json_child(path, key), "texCoord", kIndex);
    if (obj[key].is_object()) texture_transform(obj[key], json_child(path, key));
  };
  check(doc, "", "scene", kIndex);
  each(doc, "", "scenes", [&](const auto& s, const std::string& p) { check_indices(s, p, "nodes"); });
  each(doc, "", "nodes", [&](const auto& n, const std::string& p) {
    check(n, p, "mesh", kIndex);
    check(n, p, "skin", kIndex);
    check_indices(n, p, "children");
    // Not an integer, but also hidden by tinygltf, which drops a node's translation, rotation
    // and scale when it has a matrix: the specification allows one or the other, and which one
    // the file meant cannot be known.
    if (n.is_object() && n.contains("matrix"))
      for (const char* key : {"translation", "rotation", "scale"})
        if (n.contains(key))
          throw InputError(file, json_child(p, key), "a node has a matrix or translation, rotation and scale, not both");
  });
  each(doc, "", "skins", [&](const auto& k, const std::string& p) {
    check(k, p, "inverseBindMatrices", kIndex);
    check_indices(k, p, "joints");
  });
  each(doc, "", "meshes", [&](const auto& m, const std::string& mp) {
    each(m, mp, "primitives", [&](const auto& prim, const std::string& p) {
      check(prim, p, "mode", 6);
      check(prim, p, "indices", kIndex);
      check(prim, p, "material", kIndex);
      if (prim.is_object() && prim.contains("attributes") && prim["attributes"].is_object())
        for (const auto& [name, accessor] : prim["attributes"].items())
          integer(accessor, json_child(json_child(p, "attributes"), name), kIndex);
      each(prim, p, "targets", [&](const auto& target, const std::string& tp) {
        if (target.is_object())
          for (const auto& [name, accessor] : target.items()) integer(accessor, json_child(tp, name), kIndex);
      });
    });
  });
  each(doc, "", "accessors", [&](const auto& a, const std::string& p) {
    check(a, p, "bufferView", kIndex);
    check(a, p, "byteOffset", kSize);
  });
  each(doc, "", "bufferViews", [&](const auto& v, const std::string& p) {
    check(v, p, "buffer", kIndex);
    check(v, p, "byteOffset", kSize);
    check(v, p, "byteStride", kSize);
  });
  each(doc, "", "materials", [&](const auto& m, const std::string& p) {
    if (m.is_object() && m.contains("pbrMetallicRoughness"))
      texture_info(m["pbrMetallicRoughness"], json_child(p, "pbrMetallicRoughness"), "baseColorTexture");
    texture_info(m, p, "normalTexture");
    if (!m.is_object()) return;
    // pelt draws the alpha: a word or a value tinygltf would pass on unread is refused.
    if (m.contains("alphaMode")) {
      const auto& mode = m["alphaMode"];
      if (!mode.is_string() || (mode != "OPAQUE" && mode != "MASK" && mode != "BLEND"))
        throw InputError(file, json_child(p, "alphaMode"), mode.dump() + " is no alpha mode: OPAQUE, MASK or BLEND");
    }
    if (m.contains("alphaCutoff")) {
      const auto& c = m["alphaCutoff"];
      // The schema's minimum is 0; above 1 no fragment's alpha would reach it, and a MASK
      // surface would vanish without a word (elsewhere the cutoff is not drawn).
      const bool mask = m.contains("alphaMode") && m["alphaMode"] == "MASK";
      if (!c.is_number() || !(c.template get<double>() >= 0.0) || (mask && !(c.template get<double>() <= 1.0)))
        throw InputError(file, json_child(p, "alphaCutoff"),
                         c.dump() + " is no cutoff: a number from 0" + (mask ? " to 1 (alpha is at most 1)" : ""));
    }
    if (m.contains("pbrMetallicRoughness") && m["pbrMetallicRoughness"].is_object() &&
        m["pbrMetallicRoughness"].contains("baseColorFactor")) {
      const auto& f = m["pbrMetallicRoughness"]["baseColorFactor"];
      const std::string where = json_child(json_child(p, "pbrMetallicRoughness"), "baseColorFactor");
      if (!f.is_array() || f.size() != 4)
        throw InputError(file, where, "must be an array of 4 numbers");
      for (size_t k = 0; k < 4; ++k)
        if (!f[k].is_number() || !(f[k].template get<double>() >= 0.0 && f[k].template get<double>() <= 1.0))
          throw InputError(file, json_index(where, k), f[k].dump() + " is outside [0, 1]");
    }
  });
  const size_t samplers = doc.is_object() && doc.contains("samplers") && doc["samplers"].is_array()
                              ? doc["samplers"].size() : 0;
  each(doc, "", "textures", [&](const auto& t, const std::string& p) {
    check(t, p, "source", kIndex);
    check(t, p, "sampler", kIndex);
    // tinygltf keeps an index past the samplers, which drew the map with the default repeat.
    if (t.is_object() && t.contains("sampler") && t["sampler"].template get<uint64_t>() >= samplers)
      throw InputError(file, json_child(p, "sampler"),
                       "sampler " + t["sampler"].dump() + " does not exist (the file has " + std::to_string(samplers) +
                           ")");
  });
  each(doc, "", "samplers", [&](const auto& smp, const std::string& p) {
    for (const char* key : {"wrapS", "wrapT"}) {
      check(smp, p, key, kIndex);
      if (!smp.is_object() || !smp.contains(key)) continue;
      const auto mode = smp[key].template get<uint64_t>();
      if (mode != TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE && mode != TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT &&
          mode != TINYGLTF_TEXTURE_WRAP_REPEAT)
        throw InputError(file, json_child(p, key),
                         std::to_string(mode) + " is no wrap mode: 33071 (clamp to edge), 33648 (mirrored repeat) or "
                                                "10497 (repeat)");
    }
  });
  each(doc, "", "images", [&](const auto& i, const std::string& p) { check(i, p, "bufferView", kIndex); });
}

}  // namespace

LoadedMesh load_gltf(const std::filesystem::path& path, bool binary, const Budget& budget) {
  const std::string file = path.string();
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  ImageCheck check{&model, &budget, std::nullopt};
  loader.SetImageLoader(load_image_checked, &check);
  loader.SetFsCallbacks({&named_file_exists, &tinygltf::ExpandFilePath, &read_named_file, &tinygltf::WriteWholeFile,
                         &check});
  std::string err, warn;
  if (binary) check_glb_version(path, file);
  const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, file)
                         : loader.LoadASCIIFromFile(&model, &err, &warn, file);
  if (check.refused) throw InputError(file, check.refused->field, check.refused->reason);
  if (!ok) {
    err = trim(err);
    throw InputError(file, "", "malformed glTF: " + (err.empty() ? std::string("load failed") : err));
  }
  // glTF 2.0 (section 3.2): asset.version's major number is 2 for every file this layout reads;
  // a glTF 1.0 file parses in places and means something else where it does.
  if (model.asset.version.rfind("2.", 0) != 0)
    throw InputError(file, "asset.version",
                     "`" + model.asset.version + "`: pelt reads glTF 2.0 (a version 2.x), not this one");
  // glTF 2.0 (section 3.12): a loader that does not support a required extension must not
  // load the asset. pelt reads KHR_texture_transform and no other (a compressed or quantized
  // mesh, another material model would be drawn wrong).
  for (size_t i = 0; i < model.extensionsRequired.size(); ++i)
    if (model.extensionsRequired[i] != "KHR_texture_transform")
      throw InputError(file, json_index("extensionsRequired", i),
                       "the file needs the extension `" + model.extensionsRequired[i] +
                           "`, which pelt does not read (it reads core glTF 2.0 and KHR_texture_transform)");
  check_fields_as_written(gltf_json_text(path, binary), file);
  GltfReader reader(model, file, path.parent_path(), budget);
  check_face_budget(reader.triangle_count(), budget, file, "");
  LoadedMesh out = reader.read();
  add_library_warnings(out, warn);
  return out;
}

}  // namespace pelt::io::detail
