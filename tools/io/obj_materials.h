// The MTL side of OBJ loading. tinyobjloader reads what pelt hands it here: every library an
// `mtllib` record names (several on one record, a name with blanks, an absolute path), their
// text with each map statement's options read at the MTL specification's arities (tinyobjloader
// always reads three numbers after -s, -o and -t, and so took `map_Kd -s 2 2 tex.png`'s file for
// a number and dropped the map), and the maps' paths resolved from the library's own folder.
#pragma once

#include <filesystem>
#include <istream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <tiny_obj_loader.h>

#include "tools/io/map_placement.h"

namespace pelt::io::detail {

// Material names may hold blanks (`newmtl My Mat`), where tinyobjloader reads one word: pelt
// hands it the blanks as this character (in both `newmtl` and `usemtl`) and shows them again.
inline constexpr char kNameBlank = '\x1f';
std::string shown_name(std::string name);

// An `mtllib` record tinyobjloader loads: the name it calls the reader with (its first name no
// earlier record loaded, read with tinyobjloader's own splitting) and the record's text after
// the keyword. Records it calls for no name are not listed.
struct LibraryRecord {
  std::string call;
  std::string text;
};

// What mend_mtl reads of a material that tinyobjloader does not keep: where its maps lie
// (map_Kd's, norm's and map_d's -s, -o and -clamp, in OBJ's uv space), the channel map_d's
// -imfchan names, and which of `d` and `Tr` it gives.
struct MtlExtras {
  MapPlacement color, normal, alpha;
  char alpha_channel = 0;  // map_d -imfchan: 'r', 'g', 'b', 'm' (matte: alpha) or 'l'; 0: not given
  bool d = false, tr = false;
  // The transparency given by `Tr` alone: exporters write it both ways (1 - d as the
  // specification says, or d as 3ds Max does), so the loader says how it read it.
  bool transparency_by_tr() const { return tr && !d; }
  bool operator==(const MtlExtras&) const = default;
};

// The `mtllib` records of one OBJ file, read when tinyobjloader meets each.
class MaterialLibraries final : public tinyobj::MaterialReader {
 public:
  // `records`: in file order, as the OBJ's prescan found them.
  MaterialLibraries(std::filesystem::path obj_dir, std::vector<LibraryRecord> records);

  // Called by tinyobjloader once per listed record, in order: loads every library that record
  // names, each file once. Always true: a library not found is pelt's own warning (warnings()).
  bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* by_name, std::string* warn, std::string* err) override;

  // The folder of the library that defined material `id` (the OBJ's folder for none).
  const std::filesystem::path& folder_of(int id) const;
  // What mend_mtl read of material `id` (the defaults for none).
  const MtlExtras& extras_of(int id) const;
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  void load(const std::filesystem::path& library, std::vector<tinyobj::material_t>* materials,
            std::map<std::string, int>* by_name, std::string* warn, std::string* err);

  std::filesystem::path obj_dir_;
  std::vector<LibraryRecord> records_;
  size_t next_ = 0;                              // the record of tinyobjloader's next call
  std::vector<std::filesystem::path> loaded_;    // the library files read
  std::vector<std::filesystem::path> folder_;    // per material id
  std::vector<MtlExtras> extras_;            // per material id
  std::vector<std::string> warnings_;
};

// A file an OBJ or MTL names, as found: relative to `first` (the library's folder for a map),
// else to `second` (the OBJ's; where earlier pelt looked), with `\` read as `/` (Windows
// exports) when that finds it. Absolute names stand alone. When nothing is found, the name as
// `first` would read it, for the error message.
std::filesystem::path find_named_file(const std::string& name, const std::filesystem::path& first,
                                      const std::filesystem::path& second);

// One record of an OBJ or MTL file: its lines joined where `\` continues them (the OBJ
// specification's rule; a comment line never goes on, a `\` before a trailing comment does), the
// byte-order mark dropped from the file's first line (`first`). `lines`: how many of the file's
// lines it took; `mended`: set when the record is not the file's text as tinyobjloader would read
// it. A `\` on the file's last line continues into nothing and is dropped. (obj_loader.cpp)
bool read_record(std::istream& in, std::string& record, size_t& lines, bool first, bool& mended);

// MTL text as tinyobjloader should read it: statements read by read_record, material names' blanks
// kept (kNameBlank), and each map statement pelt reads (map_Kd, norm, map_d, bump, map_Bump) reduced
// to its file name, after its options are read at their arities, and each `d` and `Tr` to its value
// (`d -halo f` to f, a comment dropped). The placement map_Kd's, norm's and map_d's -s, -o and
// -clamp give, map_d's -imfchan, and which of `d` and `Tr` a material gives, go to `extras`, by material name as
// tinyobjloader reads it (the first material of a name, as tinyobjloader's `usemtl` finds it).
// What pelt cannot honour (a turbulent map, -t, a halo) and a map statement naming no file are
// added to `warnings`, naming `library`'s file name; a value that is not a finite number, or a
// scale of 0, throws InputError naming `library`, the line and the option.
std::string mend_mtl(const std::string& text, const std::filesystem::path& library, std::vector<std::string>& warnings,
                     std::map<std::string, MtlExtras>& extras);

}  // namespace pelt::io::detail
