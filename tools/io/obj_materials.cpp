#include "tools/io/obj_materials.h"

#include "tools/io/input_error.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string_view>
#include <system_error>

namespace pelt::io::detail {
namespace {

bool blank(char c) { return c == ' ' || c == '\t'; }

std::string_view trimmed(std::string_view s) {
  while (!s.empty() && (blank(s.front()) || s.front() == '\r')) s.remove_prefix(1);
  while (!s.empty() && (blank(s.back()) || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// The words of `s`, split at blanks.
std::vector<std::string_view> words(std::string_view s) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && blank(s[i])) ++i;
    const size_t start = i;
    while (i < s.size() && !blank(s[i])) ++i;
    if (i > start) out.push_back(s.substr(start, i - start));
  }
  return out;
}

// A record's names: split at blanks, except a blank after `\` (tinyobjloader's escape, kept
// as a blank in the name).
std::vector<std::string> names(std::string_view s) {
  std::vector<std::string> out;
  std::string name;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '\\' && i + 1 < s.size() && blank(s[i + 1])) {
      name.push_back(s[++i]);
    } else if (blank(s[i])) {
      if (!name.empty()) out.push_back(std::move(name));
      name.clear();
    } else {
      name.push_back(s[i]);
    }
  }
  if (!name.empty()) out.push_back(std::move(name));
  return out;
}

// A word written as a number. One past double's range is a number too, so that it is refused
// as one rather than taken for the start of a file name: too large (1e309) as infinity, too
// small (1e-400) as 0 with its sign (from_chars leaves the value unset for both; strtod gives
// them so).
bool is_number(std::string_view w, double& value) {
  if (!w.empty() && w.front() == '+') w.remove_prefix(1);
  const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), value);
  if (end != w.data() + w.size() || w.empty()) return false;
  if (ec == std::errc::result_out_of_range) value = std::strtod(std::string(w).c_str(), nullptr);
  return ec == std::errc() || ec == std::errc::result_out_of_range;
}

bool is_file(const std::filesystem::path& p) {
  std::error_code ec;
  return std::filesystem::is_regular_file(p, ec);
}

// A map statement's options (MTL specification, "Options for texture map statements"): how
// many values each takes. -o, -s and -t take one to three numbers.
struct MapOption {
  std::string_view name;
  int least, most;
};
constexpr MapOption kMapOptions[] = {{"-blendu", 1, 1}, {"-blendv", 1, 1},  {"-boost", 1, 1},   {"-mm", 1, 2},
                                     {"-o", 1, 3},      {"-s", 1, 3},       {"-t", 1, 3},       {"-texres", 1, 1},
                                     {"-clamp", 1, 1},  {"-bm", 1, 1},      {"-imfchan", 1, 1}, {"-type", 1, 1},
                                     {"-cc", 1, 1},     {"-colorspace", 1, 1}};

bool is_map_statement(std::string_view keyword) {
  return keyword == "map_Kd" || keyword == "norm" || keyword == "map_d" || keyword == "bump" ||
         keyword == "map_Bump" || keyword == "map_bump";
}

}  // namespace

std::string shown_name(std::string name) {
  std::replace(name.begin(), name.end(), kNameBlank, ' ');
  return name;
}

std::filesystem::path find_named_file(const std::string& name, const std::filesystem::path& first,
                                      const std::filesystem::path& second) {
  std::string slashed = name;
  std::replace(slashed.begin(), slashed.end(), '\\', '/');
  for (const std::string& n : {name, slashed}) {
    const std::filesystem::path p(n);
    if (p.is_absolute()) {
      if (is_file(p)) return p;
      continue;
    }
    if (is_file(first / p)) return first / p;
    if (is_file(second / p)) return second / p;
  }
  const std::filesystem::path p(name);
  return p.is_absolute() ? p : first / p;
}

std::string mend_mtl(const std::string& text, const std::filesystem::path& library, std::vector<std::string>& warnings,
                     std::map<std::string, MtlExtras>& extras) {
  std::string out, material, key;
  out.reserve(text.size());
  // Statements as OBJ records are read (read_record): continued by `\` on the next line (until
  // 2026-11-28 tinyobjloader took the `\` for a word: `map_Kd \` named the file `\`), the
  // byte-order mark dropped; a statement is named by its first line.
  std::istringstream in(text);
  std::string record;
  size_t lines = 0;
  bool mended = false;  // read_record's note for an OBJ; this text is always given as rewritten
  for (size_t line_number = 1; read_record(in, record, lines, line_number == 1, mended); line_number += lines) {
    const std::string_view line = record;
    const std::vector<std::string_view> w = words(line);
    if (w.empty() || w[0].front() == '#') {
      out.append(line).push_back('\n');
      continue;
    }
    if (w[0] == "newmtl") {
      std::string name(trimmed(line.substr(line.find("newmtl") + 6)));
      material = name;
      std::replace_if(name.begin(), name.end(), blank, kNameBlank);
      key = extras.contains(name) ? std::string() : name;  // a repeated name: tinyobjloader uses the first
      if (!key.empty()) extras[key] = {};
      out.append("newmtl ").append(name).push_back('\n');
      continue;
    }
    if (w[0] == "d" || w[0] == "Tr") {
      // Drawn (a blend, LoadedMesh::maps) since 2026-11-27: tinyobjloader reads a word that is no
      // number as 0, and `d -halo f` (the specification's) as 0, so both would turn a material
      // invisible or opaque without a word.
      size_t k = 1;
      if (w[0] == "d" && k < w.size() && w[k] == "-halo") {
        warnings.push_back("`d -halo` of material `" + material + "` in " + library.filename().string() +
                           ": pelt does not thin the material toward its silhouette, and blends it by the value alone");
        ++k;
      }
      const std::string at = "line " + std::to_string(line_number) + " `" + std::string(w[0]) + "`";
      double value = 0.0;
      // A comment may follow the value, with or without a blank (`d 0.5#half`, as tinyobjloader reads it).
      std::string_view word = k < w.size() ? w[k].substr(0, w[k].find('#')) : std::string_view();
      if (word.empty()) k = w.size();
      if (k >= w.size())
        throw InputError(library.string(), at, "has no value (a number, 1 for opaque)");
      if (!is_number(word, value) || !std::isfinite(value))
        throw InputError(library.string(), at,
                         "`" + std::string(word) + "` is not a finite number" +
                             (word.find(',') != std::string_view::npos ? " (a decimal point, not a comma)" : ""));
      // The specification's range: tinyobjloader would take `d 2` as opaque and `d -0.5` as
      // invisible, without a word.
      if (value < 0.0 || value > 1.0)
        throw InputError(library.string(), at,
                         "`" + std::string(word) + "` is outside [0, 1] (" +
                             (w[0] == "d" ? "1 for opaque, 0 for invisible" : "0 for opaque, 1 for invisible") + ")");
      if (!key.empty()) (w[0] == "d" ? extras[key].d : extras[key].tr) = true;
      out.append(w[0]).append(" ").append(word).push_back('\n');
      continue;
    }
    if (!is_map_statement(w[0])) {
      out.append(line).push_back('\n');
      continue;
    }
    // The options, then the file name: the rest of the statement, blanks and all.
    bool turbulent = false;
    MapPlacement placement;
    float scale[2] = {1.0f, 1.0f}, offset[2] = {0.0f, 0.0f};
    const std::string at = "line " + std::to_string(line_number) + " `" + std::string(w[0]) + "`";
    const bool placed = w[0] == "map_Kd" || w[0] == "norm" || w[0] == "map_d";
    char channel = 0;
    size_t k = 1;
    while (k < w.size() && w[k].size() > 1 && w[k].front() == '-') {
      const auto* option = std::find_if(std::begin(kMapOptions), std::end(kMapOptions),
                                        [&](const MapOption& o) { return o.name == w[k]; });
      if (option == std::end(kMapOptions)) break;  // a file whose name begins with `-`
      const std::string_view name = w[k++];
      // Its values: `least` words whatever they are (-clamp on), then only numbers, so
      // `-s 2 2 tex.png` ends at the file.
      for (int taken = 0; taken < option->most && k < w.size(); ++taken, ++k) {
        double value = 0.0;
        const bool number = is_number(w[k], value);
        if (taken >= option->least && !number) break;
        if (name == "-imfchan" && w[0] == "map_d") {  // the channel its dissolve is read from
          const std::string_view c = w[k];
          if (c.size() != 1 || std::string_view("rgbml").find(c[0]) == std::string_view::npos)
            throw InputError(library.string(), at + " -imfchan",
                             "`" + std::string(c) + "` is no channel pelt reads a dissolve from: r, g, b, m (the "
                             "alpha) or l (the luminance)");
          channel = c[0];
        }
        if (name == "-clamp") {
          std::string v(w[k]);
          std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return char(std::tolower(c)); });
          if (v == "on") placement.wrap_u = placement.wrap_v = raster::Wrap::Clamp;
          else if (v != "off" && placed)
            throw InputError(library.string(), at + " -clamp", "`" + std::string(w[k]) + "` is neither on nor off");
        }
        // -s and -o take at least one number: a word that is none would be lost.
        if (!number && placed && (name == "-s" || name == "-o"))
          throw InputError(library.string(), at + " " + std::string(name),
                           "`" + std::string(w[k]) + "` is not a number" +
                               (w[k].find(',') != std::string_view::npos ? " (a decimal point, not a comma)" : ""));
        if (!number || (name != "-s" && name != "-o" && name != "-t")) continue;
        if (name == "-t") {
          turbulent |= value != 0.0;
          continue;
        }
        // Only the maps pelt draws are placed, and so checked (a bump map is only warned of).
        if (!placed || taken > 1) continue;  // w: a 3-D texture's, no axis of a 2-D map
        // from_chars reads `inf` and `nan`
        if (!std::isfinite(value) || std::abs(value) > kMostMapValue)
          throw InputError(library.string(), at + " " + std::string(name),
                           "`" + std::string(w[k]) + "` is not a finite number of a sensible size");
        if (name == "-s" && std::abs(value) < kLeastMapScale)
          throw InputError(library.string(), at + " -s", tiny_scale_reason(std::string(w[k])));
        (name == "-s" ? scale : offset)[taken] = float(value);
      }
    }
    placement.m = {scale[0], 0.0f, offset[0], 0.0f, scale[1], offset[1]};
    std::string who(1, '`');
    who.append(w[0]).append("` of material `").append(material).append("` in ").append(library.filename().string());
    std::string file;
    if (k < w.size()) file = std::string(trimmed(line.substr(size_t(w[k].data() - line.data()))));
    if (file.empty()) {
      warnings.push_back(who + " names no file: no map is drawn");
      out.push_back('\n');
      continue;
    }
    if (turbulent)
      warnings.push_back(who + " is turbulent (-t), which pelt does not apply: the map is drawn without it");
    if (!key.empty()) {
      if (w[0] == "map_Kd") extras[key].color = placement;
      if (w[0] == "norm") extras[key].normal = placement;
      if (w[0] == "map_d") {
        extras[key].alpha = placement;
        extras[key].alpha_channel = channel;
      }
    }
    out.append(w[0]).append(" ").append(file).push_back('\n');
  }
  return out;
}

MaterialLibraries::MaterialLibraries(std::filesystem::path obj_dir, std::vector<LibraryRecord> records)
    : obj_dir_(std::move(obj_dir)), records_(std::move(records)) {}

const MtlExtras& MaterialLibraries::extras_of(int id) const {
  static const MtlExtras kNone;
  return id >= 0 && size_t(id) < extras_.size() ? extras_[size_t(id)] : kNone;
}

const std::filesystem::path& MaterialLibraries::folder_of(int id) const {
  return id >= 0 && size_t(id) < folder_.size() ? folder_[size_t(id)] : obj_dir_;
}

bool MaterialLibraries::operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                                   std::map<std::string, int>* by_name, std::string* warn, std::string* err) {
  // The prescan listed the calls tinyobjloader makes, in its order; one out of step (never
  // seen) finds its record by name.
  size_t r = next_;
  while (r < records_.size() && records_[r].call != name) ++r;
  if (r >= records_.size()) return true;
  next_ = r + 1;
  const std::string& record = records_[r].text;
  // One library whose name holds blanks, or several names (the specification's list).
  std::vector<std::filesystem::path> files;
  if (const std::filesystem::path whole = find_named_file(record, obj_dir_, obj_dir_); is_file(whole)) {
    files.push_back(whole);
  } else {
    for (const std::string& n : names(record)) {
      const std::filesystem::path found = find_named_file(n, obj_dir_, obj_dir_);
      if (const std::string reason = unreadable_file_reason(found); reason.empty())
        files.push_back(found);
      else  // a folder reads as nothing, a pipe without end
        warnings_.push_back("material library `" + n + "` " + reason + " (looked for " + found.string() +
                            "): its materials are not drawn");
    }
  }
  for (const std::filesystem::path& f : files) {
    std::error_code ec;
    const std::filesystem::path key = std::filesystem::weakly_canonical(f, ec);
    if (std::find(loaded_.begin(), loaded_.end(), key) != loaded_.end()) continue;
    loaded_.push_back(key);
    load(f, materials, by_name, warn, err);
  }
  return true;
}

void MaterialLibraries::load(const std::filesystem::path& library, std::vector<tinyobj::material_t>* materials,
                             std::map<std::string, int>* by_name, std::string* warn, std::string* err) {
  std::ifstream in(library, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::map<std::string, MtlExtras> extras;
  std::istringstream mended(mend_mtl(text, library, warnings_, extras));
  const size_t before = materials->size();
  tinyobj::LoadMtl(by_name, materials, &mended, warn, err);
  folder_.resize(materials->size(), obj_dir_);
  extras_.resize(materials->size());
  for (size_t id = before; id < materials->size(); ++id) {
    folder_[id] = library.parent_path();
    if (const auto it = extras.find((*materials)[id].name); it != extras.end()) extras_[id] = it->second;
  }
}

}  // namespace pelt::io::detail
