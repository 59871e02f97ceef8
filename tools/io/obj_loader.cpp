// Wavefront OBJ through tinyobjloader.
#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <tuple>
#include <unordered_map>

#include <glm/geometric.hpp>
#include <tiny_obj_loader.h>

#include "tools/io/dissolve_map.h"
#include "tools/io/input_error.h"
#include "tools/io/mesh_loader_detail.h"
#include "tools/io/obj_materials.h"
#include "tools/io/polygon_triangulation.h"

namespace pelt::io::detail {
namespace {

// A vertex of the mesh: an `f` corner's indices, and the smoothing key its normal is computed
// with (smoothing_key; 0 where the file's normals are used).
struct CornerKey {
  tinyobj::index_t idx;
  uint64_t smoothing = 0;
};
struct CornerHash {
  size_t operator()(const CornerKey& k) const {
    uint64_t h = static_cast<uint32_t>(k.idx.vertex_index) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<uint32_t>(k.idx.texcoord_index) * 0xC2B2AE3D27D4EB4Full + (h >> 29);
    h ^= static_cast<uint32_t>(k.idx.normal_index) * 0x165667B19E3779F9ull + (h >> 31);
    h ^= k.smoothing * 0xD6E8FEB86659FD93ull + (h >> 27);
    return static_cast<size_t>(h);
  }
};
struct CornerEq {
  bool operator()(const CornerKey& a, const CornerKey& b) const {
    return a.idx.vertex_index == b.idx.vertex_index && a.idx.texcoord_index == b.idx.texcoord_index &&
           a.idx.normal_index == b.idx.normal_index && a.smoothing == b.smoothing;
  }
};

// Which copies of a position share a computed normal: those of one smoothing group (`s N`), or,
// for a face in no group (`s off`, `s 0`), only the face's own corners, so it is flat. Group
// numbers are below 2^31, face numbers are set apart by bit 32.
uint64_t smoothing_key(unsigned group, size_t face) {
  return group != 0 ? uint64_t{group} : (uint64_t{1} << 32) | uint64_t(face);
}

const char* non_finite(const float* v, int n) {
  for (int k = 0; k < n; ++k) {
    if (std::isnan(v[k])) return "NaN";
    if (std::isinf(v[k])) return "infinite";
  }
  return nullptr;
}

// Names a face for error messages: its 1-based number among the file's faces, as a user
// counting `f` lines would.
std::string face_name(size_t face) { return "f " + std::to_string(face + 1); }

// tinyobjloader keeps a face's corner count in a byte.
constexpr uint64_t kMaxCorners = 255;

constexpr const char* kIndexOf[3] = {"vertex", "texture coordinate", "normal"};
constexpr const char* kCountOf[3] = {"vertices", "texture coordinates", "normals"};

// Checks one corner of an `f` record (v, v/vt, v//vn or v/vt/vn) against the records read
// so far (`counts`: v, vt, vn). tinyobjloader reads an index with atoi, so a word becomes
// 0 and a number past int's range is undefined, and it resolves a negative (relative)
// index when it reads it: an index that reaches before the first record would be taken
// for "none" (texture coordinates, normals) or fail later under another number. Indices
// past the end are checked after parsing, against the whole file (load_obj). Returns the
// reason, or an empty string.
std::string check_corner(std::string_view tok, const size_t counts[3]) {
  // Messages are built only on the error path: a large file has millions of corners.
  const auto malformed = [&] {
    std::string m = "`";
    m.append(tok).append("` is not a corner (v, v/vt, v//vn or v/vt/vn)");
    return m;
  };
  size_t start = 0;
  for (int kind = 0; kind < 3; ++kind) {
    const size_t slash = tok.find('/', start);
    const size_t end = slash == std::string_view::npos ? tok.size() : slash;
    if (!(kind == 1 && end == start && slash != std::string_view::npos)) {  // v//vn has no vt
      const std::string_view part = tok.substr(start, end - start);
      const char* b = part.data();
      const char* e = b + part.size();
      if (b != e && *b == '+') ++b;
      long long value = 0;
      const auto [ptr, ec] = std::from_chars(b, e, value);
      if (b == e || ptr != e || (ec != std::errc() && ec != std::errc::result_out_of_range)) return malformed();
      const auto index = [&] { return std::string(kIndexOf[kind]) + " index " + std::string(part); };
      if (ec == std::errc::result_out_of_range || value > INT_MAX || value < INT_MIN) return index() + " out of range";
      if (value == 0) return index() + ": OBJ numbers its records from 1";
      if (value < 0 && static_cast<unsigned long long>(-value) > counts[kind])
        return index() + " out of range (" + std::to_string(counts[kind]) + " " + kCountOf[kind] +
               " before this face)";
    }
    if (slash == std::string_view::npos) return {};
    start = slash + 1;
  }
  return malformed();  // a fourth part
}

// One line of the file as tinyobjloader splits them (its safeGetline): ended by "\n", "\r\n" or a
// lone "\r", so that no record hides inside another line from the checks below (`# note\rs x`).
bool read_line(std::istream& in, std::string& line) {
  line.clear();
  std::streambuf* sb = in.rdbuf();
  for (;;) {
    const int c = sb->sbumpc();
    if (c == std::char_traits<char>::eof()) return !line.empty();
    if (c == '\n') return true;
    if (c == '\r') {
      if (sb->sgetc() == '\n') sb->sbumpc();
      return true;
    }
    line.push_back(static_cast<char>(c));
  }
}

// Whether the line's first word, at i, is the record `kind` (`f`, `s`, `vn`): the word, then a
// blank or the line's end.
bool starts_record(const std::string& line, size_t i, std::string_view kind) {
  const size_t end = i + kind.size();
  return line.compare(i, kind.size(), kind) == 0 && (end == line.size() || line[end] == ' ' || line[end] == '\t');
}

// The next word of `line` from `pos`, split as tinyobjloader splits words: at blanks (space,
// tab) only, so `1\f2` is one word, where a stream would read two (and the checks below would
// pass a face or a position tinyobjloader reads otherwise). Empty at the line's end.
std::string_view next_word(std::string_view line, size_t& pos) {
  const size_t b = line.find_first_not_of(" \t", pos);
  if (b == std::string_view::npos) return {};
  pos = std::min(line.find_first_of(" \t", b), line.size());
  return line.substr(b, pos - b);
}

// Whether `t` is a decimal number as tinyobjloader reads one: [+-], digits with an optional
// `.` and fraction (at least one digit in all), then an optional exponent e[+-]digits. strtod
// also takes hexadecimal (`0x1`), which tinyobjloader reads as the 0 before the `x`.
bool is_decimal(std::string_view t) {
  size_t k = 0;
  const auto digits = [&] {
    const size_t from = k;
    while (k < t.size() && t[k] >= '0' && t[k] <= '9') ++k;
    return k - from;
  };
  if (k < t.size() && (t[k] == '+' || t[k] == '-')) ++k;
  size_t mantissa = digits();
  if (k < t.size() && t[k] == '.') ++k, mantissa += digits();
  if (mantissa == 0) return false;
  if (k < t.size() && (t[k] == 'e' || t[k] == 'E')) {
    ++k;
    if (k < t.size() && (t[k] == '+' || t[k] == '-')) ++k;
    if (digits() == 0) return false;
  }
  return k == t.size();
}

// How many numbers a `v` (kind 0), `vt` (1) or `vn` (2) record may have. tinyobjloader fills
// missing numbers with 0 and drops extra ones without a word. A position's w weights rational
// curves and surfaces, not polygons, and its r g b are vertex colours, which pelt does not
// draw: both forms give x y z as they are. Returns the reason, or an empty string.
std::string check_number_count(int kind, size_t n) {
  const std::string has = ", this one has " + std::to_string(n);
  if (kind == 0)
    return n == 3 || n == 4 || n == 6 ? "" : "a position is 3 numbers (x y z), 4 (x y z w) or 6 (x y z r g b)" + has;
  if (kind == 1) return n >= 1 && n <= 3 ? "" : "a texture coordinate is 1 to 3 numbers (u [v [w]])" + has;
  return n == 3 ? "" : "a normal is 3 numbers (x y z)" + has;
}

// What one pass over the file finds before tinyobjloader sees it.
struct ObjPrescan {
  // Triangles the faces make, each `f` line of k corners split into k - 2 (as
  // triangulate_polygon does); saturating.
  uint64_t triangles = 0;
  // The first malformed or non-finite number, record of too few or too many numbers, or face
  // of fewer than three corners (see below), thrown only after the budget check so that an
  // oversized file is refused for its size whatever follows.
  std::optional<InputError> bad_record;
  // An `s` record was seen, and a corner without a normal index: only then (or when a given
  // normal has zero length) do smoothing groups decide the computed normals (a file without `s`
  // records is smoothed whole, as pelt always did; a file that gives every normal needs none computed).
  bool smoothing_groups = false;
  bool corner_without_normal = false;
  // Valid OBJ that tinyobjloader misreads, mended in memory first (mend_obj): a byte-order
  // mark, a line continued by `\`, a comment after a face's corners, a material name with
  // blanks.
  bool needs_mending = false;
  // The `mtllib` records tinyobjloader will load, in order: the word it calls the reader with,
  // and the record's text after the keyword (MaterialLibraries reads them).
  std::vector<LibraryRecord> libraries;
  // Each `usemtl` record: the face it comes before (0-based, in file order) and the name as
  // tinyobjloader reads it. tinyobjloader looks a name up when it meets the record, so a
  // material whose `mtllib` comes later is lost to it; these find it after the parse.
  struct MaterialUse {
    uint64_t first_face;
    std::string name;
    // The name before a blank and `#` (`usemtl Mat # note`), empty without one: a name may hold
    // `#` (3ds Max's `Material #25`), so this is tried only when the whole name is no material's.
    std::string before_comment;
    size_t line = 0;
  };
  std::vector<MaterialUse> uses;
  // Records and face corners, for the memory a parse holds (load_bytes_at_least).
  uint64_t positions = 0, texcoords = 0, normals = 0, faces = 0, corners = 0;
};

// The least a parse of the prescanned file holds at once, in the pelt process: tinyobjloader's
// arrays as it returns them (a position 3 floats and a weight, a texture coordinate 2, a normal
// 3; a corner 3 indices; a face its corner count, material and smoothing group: 9 bytes), the
// mended text when there is one, and the process itself. The parse holds more (each face's own
// vector while it reads, pelt's mesh after), so a budget below this is certainly exceeded.
uint64_t load_bytes_at_least(const ObjPrescan& pre, uint64_t mended_text) {
  uint64_t bytes = kProcessBaselineBytes + mended_text;
  bytes = sat_add(bytes, sat_mul(pre.positions, 16));
  bytes = sat_add(bytes, sat_mul(pre.texcoords, 8));
  bytes = sat_add(bytes, sat_mul(pre.normals, 12));
  bytes = sat_add(bytes, sat_mul(pre.corners, 12));
  return sat_add(bytes, sat_mul(pre.faces, 9));
}

// tinyobjloader's warnings, a line each, less those pelt knows to be untrue or says better: its
// "not found" for a name a library defines (it met the `usemtl` before the `mtllib`) or that a
// comment was cut from (`found`), and its note on a material giving both `d` and `Tr` (3ds Max
// writes both for every material; pelt's own transparency warning covers what matters).
std::string untrue_warnings_dropped(const std::string& warnings, const std::map<std::string, int>& defined,
                                    const std::set<std::string>& found) {
  static constexpr std::string_view kNotFoundHead = "material [ '", kNotFoundTail = "' ] not found in .mtl";
  std::string kept;
  std::istringstream lines(warnings);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("Both `d` and `Tr` parameters defined", 0) == 0) continue;
    if (line.size() > kNotFoundHead.size() + kNotFoundTail.size() && line.starts_with(kNotFoundHead) &&
        line.ends_with(kNotFoundTail)) {
      const std::string name =
          line.substr(kNotFoundHead.size(), line.size() - kNotFoundHead.size() - kNotFoundTail.size());
      if (defined.contains(name) || found.contains(name)) continue;
    }
    kept.append(line).push_back('\n');
  }
  return kept;
}

// The text after a record's keyword at i: blanks trimmed, and a trailing comment (a word that
// begins with `#`) cut off, except in a name (`usemtl Material #2`, `mtllib my #1.mtl`).
std::string record_text(const std::string& line, size_t i, size_t keyword, bool name = false) {
  std::string t = line.substr(std::min(line.size(), i + keyword));
  if (!name)
    for (size_t h = t.find('#'); h != std::string::npos; h = t.find('#', h + 1))
      if (h == 0 || t[h - 1] == ' ' || t[h - 1] == '\t') {
        t.resize(h);
        break;
      }
  const size_t a = t.find_first_not_of(" \t"), b = t.find_last_not_of(" \t");
  return a == std::string::npos ? std::string() : t.substr(a, b - a + 1);
}

bool names_something(const std::string& line, size_t i) {
  for (const char* k : {"usemtl", "mtllib", "newmtl", "o", "g"})
    if (starts_record(line, i, k)) return true;
  return false;
}

// Whether `line` goes on in the next one: its last character before trailing blanks, and
// before a trailing comment (but in a name), is `\` (the OBJ specification's continuation). A
// comment line never goes on.
bool continues(const std::string& line) {
  // Every line of the file passes here: without a `\` or a `#` in it (nearly every line) the
  // answer needs no copy of the record's text.
  if (line.find_first_of("\\#") == std::string::npos) return false;
  const size_t i = line.find_first_not_of(" \t");
  if (i == std::string::npos || line[i] == '#') return false;
  const std::string text = record_text(line, i, 0, names_something(line, i));
  return !text.empty() && text.back() == '\\';
}

}  // namespace

bool read_record(std::istream& in, std::string& record, size_t& lines, bool first, bool& mended) {
  if (!read_line(in, record)) return false;
  lines = 1;
  if (first && record.rfind("\xEF\xBB\xBF", 0) == 0) {
    record.erase(0, 3);  // tinyobjloader would take the mark for part of the first word
    mended = true;
  }
  std::string next;
  while (continues(record)) {
    mended = true;
    const size_t i = record.find_first_not_of(" \t");
    // Keep what precedes the `\` (a comment after it went with the record's end anyway).
    const std::string body = record_text(record, i, 0, names_something(record, i));
    record = record.substr(0, i) + body.substr(0, body.size() - 1);
    if (!read_line(in, next)) break;
    record.append(" ").append(next);
    ++lines;
  }
  return true;
}

namespace {

// What tinyobjloader calls its MaterialReader with for an `mtllib` record (`rest`: the text
// after `mtllib `): its names split at blanks, `\` escaping the next character, and the first
// that no earlier call loaded; none when every name was (`loaded` is tinyobjloader's set).
std::optional<std::string> library_call(const std::string& rest, std::set<std::string>& loaded) {
  std::vector<std::string> names;
  std::string token;
  bool escaping = false;
  for (char ch : rest) {
    if (escaping) {
      escaping = false;
    } else if (ch == '\\') {
      escaping = true;
      continue;
    } else if (ch == ' ') {
      if (!token.empty()) names.push_back(token);
      token.clear();
      continue;
    }
    token += ch;
  }
  names.push_back(token);
  for (const std::string& n : names)
    if (loaded.insert(n).second) return n;
  return std::nullopt;
}

// An `s` record's argument: `off`, or a group number, 0 meaning off (the OBJ specification).
// tinyobjloader reads any other word as 0 and a negative number as 0, without a word; both would
// silently flatten the faces that follow. Returns the reason, or an empty string.
std::string check_smoothing_group(std::string_view arg) {
  if (arg.empty()) return "an `s` record needs `off` or a group number";
  if (arg == "off") return {};
  const char* b = arg.data() + (arg[0] == '+' ? 1 : 0);
  const char* e = arg.data() + arg.size();
  unsigned long long value = 0;
  const auto [ptr, ec] = std::from_chars(b, e, value);
  // tinyobjloader reads the number into an int and takes a negative one for 0: past INT_MAX a
  // group would silently be off.
  if (b == e || ptr != e || ec != std::errc() || value > INT_MAX) {
    std::string m = "`";
    return m.append(arg).append("` is not a smoothing group: `s off`, `s 0` (off) or a group number up to ")
        .append(std::to_string(INT_MAX));
  }
  return {};
}

// tinyobjloader reads a malformed number ("nan", "1.2.3", "abc") as 0 without a word,
// so the numeric records are checked here first, numbered as the file numbers them
// (`v 3` is the third `v` record). Each value must be a complete decimal number (is_decimal);
// NaN and infinities (including overflow such as 1e999) are reported by name; a record must
// have as many numbers as its kind takes (check_number_count). The same pass
// counts the triangles, one line in memory at a time, so the face budget is checked
// before anything proportional to the file is allocated. A face of one or two corners is
// reported too: tinyobjloader drops it without a word, leaving a hole in the mesh; so is a
// face of more corners than tinyobjloader can count, and a corner it would misread
// (check_corner).
ObjPrescan prescan_obj(std::istream& in, const std::string& file) {
  ObjPrescan out;
  std::string line, tok;
  size_t counts[3] = {0, 0, 0};  // v, vt, vn
  static const char* kWhat[3] = {"position", "texture coordinate", "normal"};
  size_t line_number = 0, faces = 0, smoothing_records = 0, lines = 1;
  std::set<std::string> loaded;  // tinyobjloader's set of library names
  // Records, not lines: a continued record is checked joined, named by its first line.
  for (; read_record(in, line, lines, line_number == 0, out.needs_mending); line_number += lines - 1) {
    ++line_number;
    size_t i = line.find_first_not_of(" \t");
    if (i == std::string::npos) continue;
    if (starts_record(line, i, "mtllib")) {
      // tinyobjloader takes the text after `mtllib` and one character (its token + 7).
      const std::string rest = line.substr(std::min(line.size(), i + 7));
      if (std::optional<std::string> word = library_call(rest, loaded))
        out.libraries.push_back({*word, record_text(line, i, 6, true)});
      continue;
    }
    if (starts_record(line, i, "usemtl")) {
      std::string name = record_text(line, i, 6, true);
      if (name.find_first_of(" \t") != std::string::npos) out.needs_mending = true;
      std::string before = record_text(line, i, 6, false);
      if (before == name) before.clear();
      for (std::string* n : {&name, &before})
        std::replace_if(n->begin(), n->end(), [](char c) { return c == ' ' || c == '\t'; }, kNameBlank);
      out.uses.push_back({faces, std::move(name), std::move(before), line_number});
      continue;
    }
    if (starts_record(line, i, "f")) {
      uint64_t corners = 0;
      const std::string where = " (line " + std::to_string(line_number) + ")";
      bool comment = false;
      size_t pos = i + 1;
      for (std::string_view corner; !(corner = next_word(line, pos)).empty();) {
        if (corner[0] == '#') {
          comment = true;
          break;
        }
        ++corners;
        // v, v/vt: no normal (v//vn and v/vt/vn have a second slash)
        if (std::count(corner.begin(), corner.end(), '/') < 2) out.corner_without_normal = true;
        if (out.bad_record) continue;
        if (std::string reason = check_corner(corner, counts); !reason.empty())
          out.bad_record.emplace(file, face_name(faces), reason + where);
      }
      ++faces;
      out.corners = sat_add(out.corners, corners);
      if (corners >= 3) out.triangles = sat_add(out.triangles, corners - 2);
      if (out.bad_record) continue;
      if (comment) out.needs_mending = true;  // tinyobjloader would read `#` as a corner
      if (corners < 3)
        out.bad_record.emplace(file, face_name(faces - 1),
                               "a face needs at least 3 vertices, this one has " + std::to_string(corners) + where);
      else if (corners > kMaxCorners)
        out.bad_record.emplace(file, face_name(faces - 1),
                               "a face has at most " + std::to_string(kMaxCorners) + " vertices here, this one has " +
                                   std::to_string(corners) + where);
      continue;
    }
    if (starts_record(line, i, "s")) {
      out.smoothing_groups = true;
      ++smoothing_records;
      if (out.bad_record) continue;
      std::istringstream tokens(line.substr(i + 1));
      std::string arg, extra;
      tokens >> arg;
      if (!arg.empty() && arg[0] == '#') arg.clear();
      if (tokens >> extra && extra[0] != '#') arg.append(" ").append(extra);
      if (std::string reason = check_smoothing_group(arg); !reason.empty())
        out.bad_record.emplace(file, "s " + std::to_string(smoothing_records),
                               reason + " (line " + std::to_string(line_number) + ")");
      continue;
    }
    if (out.bad_record) continue;
    // A bare `v`, `vt` or `vn` is a record too: tinyobjloader skips it, which would shift every
    // later record of its kind onto the wrong number.
    int kind;
    if (starts_record(line, i, "v")) kind = 0, i += 1;
    else if (starts_record(line, i, "vt")) kind = 1, i += 2;
    else if (starts_record(line, i, "vn")) kind = 2, i += 2;
    else continue;
    const std::string record = std::string(kind == 0 ? "v " : kind == 1 ? "vt " : "vn ") +
                               std::to_string(++counts[kind]);
    const auto where = [&] { return " (line " + std::to_string(line_number) + ")"; };
    size_t numbers = 0;
    for (std::string_view word; !(word = next_word(line, i)).empty();) {
      if (word[0] == '#') break;
      tok.assign(word);
      ++numbers;
      char* end = nullptr;
      const double v = std::strtod(tok.c_str(), &end);
      if (end != tok.c_str() + tok.size()) {
        out.bad_record.emplace(file, record, "`" + tok + "` is not a number" + where());
        break;
      }
      if (std::isnan(v)) {
        out.bad_record.emplace(file, record, std::string(kWhat[kind]) + " is NaN");
        break;
      }
      if (std::isinf(v) || std::abs(v) > 3.4028234663852886e38) {
        out.bad_record.emplace(file, record, std::string(kWhat[kind]) + " is infinite");
        break;
      }
      if (!is_decimal(tok)) {
        out.bad_record.emplace(file, record, "`" + tok + "` is not a decimal number" + where());
        break;
      }
    }
    if (out.bad_record) continue;
    if (std::string reason = check_number_count(kind, numbers); !reason.empty())
      out.bad_record.emplace(file, record, reason + where());
  }
  out.positions = counts[0];
  out.texcoords = counts[1];
  out.normals = counts[2];
  out.faces = faces;
  return out;
}

// The file's text as tinyobjloader should read it (ObjPrescan::needs_mending), line for line so
// that every message's line number is still the file's: the byte-order mark dropped, a
// continued record joined onto its first line (the lines it took left empty), a comment after a
// face's corners (or a line's or point's) cut off, and a material name's blanks kept
// (kNameBlank).
std::string mend_obj(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string out, line;
  size_t lines = 1;
  bool mended = false;
  for (bool first = true; read_record(in, line, lines, first, mended); first = false) {
    const size_t i = line.find_first_not_of(" \t");
    if (i != std::string::npos) {
      if (starts_record(line, i, "f") || starts_record(line, i, "l") || starts_record(line, i, "p")) {
        line = line.substr(i, 1) + " " + record_text(line, i, 1);
      } else if (starts_record(line, i, "usemtl")) {
        std::string name = record_text(line, i, 6, true);
        std::replace_if(name.begin(), name.end(), [](char c) { return c == ' ' || c == '\t'; }, kNameBlank);
        line = "usemtl " + name;
      }
    }
    out.append(line).push_back('\n');
    out.append(lines - 1, '\n');
  }
  return out;
}

// " (line N)" of face `face` (0-based, in file order), found by reading the file again: only an
// error needs it, so no line number is kept per face of a large file.
std::string face_line(const std::filesystem::path& path, size_t face) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  size_t faces = 0, lines = 1;
  bool mended = false;
  for (size_t number = 1; read_record(in, line, lines, number == 1, mended); number += lines) {
    const size_t i = line.find_first_not_of(" \t");
    if (i != std::string::npos && starts_record(line, i, "f") && faces++ == face)
      return " (line " + std::to_string(number) + ")";
  }
  return "";
}

// Each face's maps, from its material (LoadedMesh::maps, triangle_maps): materials naming the
// same files placed alike share a set; faces of no material, beside faces with maps, get a set
// without maps. A map's name is read from its library's folder, as exporters write it (until
// 2026-11-27 from the OBJ's, where pelt still looks when the library's folder has no such
// file). Until 2026-11-27 the first face's maps were drawn on the whole mesh.
void take_material_maps(LoadedMesh& out, const std::vector<tinyobj::material_t>& materials,
                        const MaterialLibraries& libraries, const std::filesystem::path& dir,
                        const std::vector<char>& material_used, const std::vector<int>& triangle_material,
                        size_t faces_without_material, const Budget& budget) {
  std::vector<MeshMaps> sets_of(materials.size() + 1);  // by material id; the last: no material
  // Each colour and dissolve pair read once: (map_Kd's file or none, map_d's, map_d's channel).
  std::map<std::tuple<std::string, std::string, char>, std::shared_ptr<const ImageRGBA>> dissolved;
  uint64_t dissolved_bytes = 0;  // what those images hold, for the next pair's budget
  sets_of.back().material = kNoMaterial;
  for (size_t id = 0; id < materials.size(); ++id) {
    if (!material_used[id]) continue;
    const tinyobj::material_t& mat = materials[id];
    MeshMaps& set = sets_of[id];
    set.material = mat.name;
    // `d` (or `Tr`, which tinyobjloader reads as 1 - d) between 0 and 1 blends the faces by it, as
    // glTF's BLEND with that factor alpha, times the colour map's alpha where it has one (as
    // three.js's and Blender's importers read it). `d 0` is left opaque (see load_obj's warnings).
    if (mat.dissolve > 0.0 && mat.dissolve < 1.0) {
      set.alpha_mode = AlphaMode::blend;
      set.alpha_factor = float(mat.dissolve);
    }
    const std::filesystem::path& library_dir = libraries.folder_of(int(id));
    const MtlExtras& placements = libraries.extras_of(int(id));
    if (!mat.diffuse_texname.empty()) {
      set.color_map.path = find_named_file(mat.diffuse_texname, library_dir, dir);
      set.color_map.placement = placements.color;
    }
    if (!mat.alpha_texname.empty()) {
      // `map_d` (a dissolve map) blends the faces by it, times its colour map's alpha (three.js's
      // importer blends by it too): one image of both, read here, each pair once.
      const std::filesystem::path dissolve = find_named_file(mat.alpha_texname, library_dir, dir);
      const bool colored = set.color_map.present();
      std::shared_ptr<const ImageRGBA>& pixels =
          dissolved[{colored ? set.color_map.path.string() : std::string(), dissolve.string(), placements.alpha_channel}];
      if (!pixels)
        pixels = std::make_shared<const ImageRGBA>(
            dissolved_color_map(colored ? &set.color_map.path : nullptr, dissolve, placements.alpha_channel, budget,
                                out.warnings, dissolved_bytes));
      if (colored && !(placements.alpha == placements.color))
        out.warnings.push_back("material `" + shown_name(mat.name) + "` places `map_d " + mat.alpha_texname +
                               "` otherwise than its `map_Kd` (-s, -o, -clamp): the dissolve is read where the colour "
                               "map lies");
      set.color_map.files = colored ? std::vector{set.color_map.path, dissolve} : std::vector{dissolve};
      set.color_map.pixels = pixels;
      set.color_map.path.clear();
      if (!colored) set.color_map.placement = placements.alpha;
      set.alpha_mode = AlphaMode::blend;
      if (!(mat.dissolve > 0.0 && mat.dissolve < 1.0)) set.alpha_factor = 1.0f;
    }
    if (!mat.normal_texname.empty()) {
      set.normal_map.path = find_named_file(mat.normal_texname, library_dir, dir);
      set.normal_map.placement = placements.normal;
    } else if (!mat.bump_texname.empty()) {
      // `bump` is as often a height map as a normal map (Blender writes normal maps there,
      // Sponza height maps): not drawn, and the user hears why.
      out.warnings.push_back("material `" + shown_name(mat.name) + "` names a bump map `" + mat.bump_texname +
                             "` that is not drawn: pelt draws tangent-space normal maps, named by `norm` in the "
                             "MTL file or by the scene's normal_map");
    }
  }
  if (std::none_of(sets_of.begin(), sets_of.end(), [](const MeshMaps& m) { return m.any(); })) return;
  std::vector<uint32_t> set_of_material(sets_of.size(), UINT32_MAX);
  out.triangle_maps.reserve(triangle_material.size());
  for (const int id : triangle_material) {
    const size_t m = id >= 0 && size_t(id) < materials.size() ? size_t(id) : materials.size();
    if (set_of_material[m] == UINT32_MAX) set_of_material[m] = add_map_set(out.maps, sets_of[m]);
    out.triangle_maps.push_back(set_of_material[m]);
  }
  if (out.maps.size() == 1) out.triangle_maps.clear();
  if (faces_without_material > 0)
    out.warnings.push_back(std::to_string(faces_without_material) +
                           (faces_without_material == 1 ? " face has" : " faces have") +
                           " no material (no `usemtl` before them, or one naming no material a library "
                           "defines): they are drawn without the file's maps");
}

}  // namespace

LoadedMesh load_obj(const std::filesystem::path& path, const Budget& budget) {
  const std::string file = path.string();
  {
    std::ifstream probe(path);
    if (!probe) throw InputError(file, "", "cannot open the file for reading");
  }
  ObjPrescan pre;
  {
    std::ifstream in(path, std::ios::binary);
    pre = prescan_obj(in, file);
  }
  check_face_budget(pre.triangles, budget, file, "");
  // Only a file that needs it is held in memory, mended (the prescan read its records as the
  // mended text holds them, so the budgets and the checks are the mended file's).
  const bool mend = pre.needs_mending;
  // Before the parse allocates: --max-memory is otherwise checked once the mesh is loaded, and a
  // large file's parse holds about four times the mesh it makes.
  std::error_code size_error;
  const uintmax_t file_bytes = std::filesystem::file_size(path, size_error);
  const uint64_t at_least = load_bytes_at_least(pre, mend && !size_error ? uint64_t(file_bytes) : 0);
  if (at_least > budget.max_memory_bytes)
    throw InputError(file, "",
                     "reading it holds at least " + describe_bytes(at_least) + " (" + std::to_string(pre.positions) +
                         " positions, " + std::to_string(pre.texcoords) + " texture coordinates, " +
                         std::to_string(pre.normals) + " normals and " + std::to_string(pre.faces) + " faces of " +
                         std::to_string(pre.corners) + " corners as the OBJ reader stores them, and the pelt process "
                         "itself), " + over_budget(describe_bytes(budget.max_memory_bytes), kMaxMemoryFlag));
  if (pre.bad_record) throw *pre.bad_record;
  std::string mended;
  if (mend) mended = mend_obj(path);
  std::ifstream from_file;
  std::istringstream from_text;
  std::istream* text = &from_file;
  if (mend) {
    from_text.str(std::move(mended));
    text = &from_text;
  } else {
    from_file.open(path, std::ios::binary);
  }
  const std::filesystem::path dir = path.parent_path();
  MaterialLibraries libraries(dir, std::move(pre.libraries));
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warnings, error;
  // pelt splits polygons itself (triangulate_polygon): tinyobjloader's triangulation drops
  // a quad with an index past the end and part of some valid polygons, without a word.
  const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warnings, &error, text, &libraries,
                                   /*triangulate=*/false, /*default_vcols_fallback=*/false);
  if (!ok) {
    std::string msg = error;
    while (!msg.empty() && (msg.back() == '\n' || msg.back() == '\r')) msg.pop_back();
    throw InputError(file, "", "malformed OBJ: " + (msg.empty() ? std::string("parse failed") : msg));
  }

  LoadedMesh out;
  out.warnings = libraries.warnings();
  const size_t nv = attrib.vertices.size() / 3, nt = attrib.texcoords.size() / 2,
               nn = attrib.normals.size() / 3;
  for (size_t i = 0; i < nv; ++i)
    if (const char* bad = non_finite(&attrib.vertices[3 * i], 3))
      throw InputError(file, "v " + std::to_string(i + 1), std::string("position is ") + bad);
  for (size_t i = 0; i < nt; ++i)
    if (const char* bad = non_finite(&attrib.texcoords[2 * i], 2))
      throw InputError(file, "vt " + std::to_string(i + 1), std::string("texture coordinate is ") + bad);
  for (size_t i = 0; i < nn; ++i)
    if (const char* bad = non_finite(&attrib.normals[3 * i], 3))
      throw InputError(file, "vn " + std::to_string(i + 1), std::string("normal is ") + bad);

  std::unordered_map<CornerKey, uint32_t, CornerHash, CornerEq> vertex_of;
  // Groups decide normals pelt computes: those a corner lacks, or all of them when a given one has
  // zero length, by finish_normals' own test (a denormal one's length rounds to zero too).
  bool zero_normal = false;
  for (size_t i = 0; i < nn; ++i)
    zero_normal |= !(glm::length(glm::vec3(attrib.normals[3 * i], attrib.normals[3 * i + 1], attrib.normals[3 * i + 2])) > 0.0f);
  const bool by_smoothing = pre.smoothing_groups && (pre.corner_without_normal || zero_normal);
  std::vector<uint64_t> smoothing;  // per vertex, when by_smoothing
  bool all_normals = true;
  std::vector<uint8_t> uv_missing;         // per vertex (settle_uvs)
  std::vector<std::string> uvless_names;   // "material `a`", "no material": of faces without uvs (note_uvless)
  Mesh& m = out.mesh;
  size_t face_number = 0;
  std::vector<char> material_used(materials.size(), 0);  // by material id
  size_t faces_without_material = 0;
  // A `usemtl` before the `mtllib` that defines its material: tinyobjloader gave its faces no
  // material and warned that the name was not found. The name is looked up again among every
  // library's materials (the first of a name, as tinyobjloader's own lookup takes it).
  std::map<std::string, int> first_of_name;
  for (size_t id = 0; id < materials.size(); ++id) first_of_name.try_emplace(materials[id].name, int(id));
  size_t use = 0;
  std::set<size_t> read_as_comment;  // uses whose name was found only without its `#` comment
  std::vector<glm::vec3> corner_positions;
  std::vector<uint32_t> corner_vertices, triangles;
  std::vector<int> triangle_material;  // per triangle, its material id (-1: none)
  for (const tinyobj::shape_t& shape : shapes) {
    const auto& mesh = shape.mesh;
    size_t offset = 0;
    for (size_t f = 0; f < mesh.num_face_vertices.size(); ++f, ++face_number) {
      const unsigned corners = mesh.num_face_vertices[f];
      if (corners < 3)  // the prescan refuses such faces; tinyobjloader skips them
        throw InputError(file, face_name(face_number), "face has " + std::to_string(corners) + " vertices");
      while (use < pre.uses.size() && pre.uses[use].first_face <= face_number) ++use;
      int id = -1;
      if (f < mesh.material_ids.size()) {
        id = mesh.material_ids[f];
        if (id < 0 && use > 0) {
          const ObjPrescan::MaterialUse& u = pre.uses[use - 1];
          if (const auto it = first_of_name.find(u.name); it != first_of_name.end()) {
            id = it->second;
          } else if (const auto cut = first_of_name.find(u.before_comment);
                     !u.before_comment.empty() && cut != first_of_name.end()) {
            id = cut->second;
            read_as_comment.insert(use - 1);
          }
        }
        if (id >= 0 && size_t(id) < material_used.size()) material_used[size_t(id)] = 1;
        faces_without_material += id < 0;
      }
      corner_positions.clear();
      corner_vertices.clear();
      for (unsigned c = 0; c < corners; ++c) {
        const tinyobj::index_t idx = mesh.indices[offset + c];
        if (idx.vertex_index < 0 || static_cast<size_t>(idx.vertex_index) >= nv)
          throw InputError(file, face_name(face_number),
                           "vertex index " + std::to_string(idx.vertex_index + 1) + " out of range (" +
                               std::to_string(nv) + " vertices)" + face_line(path, face_number));
        if (idx.texcoord_index >= 0 && static_cast<size_t>(idx.texcoord_index) >= nt)
          throw InputError(file, face_name(face_number),
                           "texture coordinate index " + std::to_string(idx.texcoord_index + 1) + " out of range (" +
                               std::to_string(nt) + " texture coordinates)" + face_line(path, face_number));
        if (idx.normal_index >= 0 && static_cast<size_t>(idx.normal_index) >= nn)
          throw InputError(file, face_name(face_number),
                           "normal index " + std::to_string(idx.normal_index + 1) + " out of range (" +
                               std::to_string(nn) + " normals)" + face_line(path, face_number));
        CornerKey key{idx, 0};
        if (by_smoothing)
          key.smoothing = smoothing_key(f < mesh.smoothing_group_ids.size() ? mesh.smoothing_group_ids[f] : 0u,
                                        face_number);
        auto [it, inserted] = vertex_of.try_emplace(key, static_cast<uint32_t>(m.positions.size()));
        if (inserted) {
          if (by_smoothing) smoothing.push_back(key.smoothing);
          const float* p = &attrib.vertices[3 * idx.vertex_index];
          m.positions.emplace_back(p[0], p[1], p[2]);
          uv_missing.push_back(idx.texcoord_index < 0);
          if (idx.texcoord_index >= 0) {
            const float* t = &attrib.texcoords[2 * idx.texcoord_index];
            m.uvs.emplace_back(t[0], t[1]);
          } else {
            m.uvs.emplace_back(0.0f, 0.0f);
          }
          if (idx.normal_index >= 0) {
            const float* n = &attrib.normals[3 * idx.normal_index];
            m.normals.emplace_back(n[0], n[1], n[2]);
          } else {
            all_normals = false;
            m.normals.emplace_back(0.0f);
          }
        }
        if (idx.texcoord_index < 0) {  // every face's, also one whose corners were met before
          const std::string name = id >= 0 && size_t(id) < materials.size()
                                       ? "material `" + shown_name(materials[size_t(id)].name) + "`"
                                       : "no material";
          note_uvless(uvless_names, name);
        }
        corner_vertices.push_back(it->second);
        corner_positions.push_back(m.positions[it->second]);
      }
      triangles.clear();
      triangulate_polygon(corner_positions, triangles);
      for (uint32_t corner : triangles) m.indices.push_back(corner_vertices[corner]);
      triangle_material.insert(triangle_material.end(), triangles.size() / 3, id);
      offset += corners;
    }
  }
  if (m.indices.empty()) throw InputError(file, "", "the file has no faces");
  std::set<std::string> found;  // names read without their comment
  for (const size_t k : read_as_comment) {
    const ObjPrescan::MaterialUse& u = pre.uses[k];
    found.insert(u.name);
    out.warnings.push_back("`usemtl " + shown_name(u.name) + "` (line " + std::to_string(u.line) +
                           ") names no material: read as `" + shown_name(u.before_comment) +
                           "`, the text from `#` taken as a comment");
  }
  add_library_warnings(out, shown_name(untrue_warnings_dropped(warnings, first_of_name, found)));
  settle_uvs(out, std::move(uv_missing), "faces of", uvless_names);
  finish_normals(out, all_normals, nn > 0, NormalSharing::per_position, smoothing);

  // What a used material asks for that pelt does not draw: no surface at all.
  for (size_t id = 0; id < materials.size(); ++id) {
    if (!material_used[id]) continue;
    const tinyobj::material_t& t = materials[id];
    if (t.dissolve <= 0.0)  // tinyobjloader reads Tr as 1 - d
      out.warnings.push_back("material `" + shown_name(t.name) +
                             "` is invisible as written (`d 0` or `Tr 1`; some exporters mean opaque by `Tr 1`), which "
                             "pelt does not draw: its faces are " +
                             (t.alpha_texname.empty() ? "drawn opaque" : "blended by its `map_d` alone"));
    const bool blended = t.dissolve > 0.0 && t.dissolve < 1.0;
    char value[48];
    std::snprintf(value, sizeof value, "%g", double(float(t.dissolve)));
    if (blended && libraries.extras_of(int(id)).transparency_by_tr())
      out.warnings.push_back("material `" + shown_name(t.name) + "` gives its transparency by `Tr` alone, which "
                             "exporters write both ways: read as the specification says, an opacity of " + value +
                             " (write `d` for the opacity meant)");
    if (blended && t.dissolve < 0.01)
      out.warnings.push_back("material `" + shown_name(t.name) + "` is nearly invisible (an opacity of " +
                             std::string(value) + ")");
  }
  const bool no_face_material = std::find(material_used.begin(), material_used.end(), 1) == material_used.end();
  if (no_face_material && std::any_of(materials.begin(), materials.end(), [](const tinyobj::material_t& t) {
        return !t.diffuse_texname.empty() || !t.normal_texname.empty() || !t.alpha_texname.empty();
      }))
    out.warnings.push_back(std::string("the material libraries define maps, but no face names a material (") +
                           (pre.uses.empty() ? "no `usemtl` record" : "no face follows a `usemtl` of a defined material") +
                           "): no map is drawn");
  take_material_maps(out, materials, libraries, dir, material_used, triangle_material, faces_without_material,
                     budget);
  return out;
}

}  // namespace pelt::io::detail
