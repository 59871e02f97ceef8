#include "tools/io/json_fields.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <unordered_set>

#include <glm/geometric.hpp>

#include "tools/io/input_error.h"
#include "tools/io/suggest.h"

namespace pelt::io {
namespace {

std::string fmt(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

std::string json_child(const std::string& path, std::string_view key) {
  return path.empty() ? std::string(key) : path + "." + std::string(key);
}

std::string json_index(const std::string& path, size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

namespace {

// Walks the document as nlohmann's SAX events, keeping each open container's path, its keys
// so far (objects) or its next index (arrays); stops at the first repeated key.
class RepeatedKeyFinder : public nlohmann::json_sax<nlohmann::json> {
 public:
  std::optional<std::string> repeated;

  bool null() override { return element(); }
  bool boolean(bool) override { return element(); }
  bool number_integer(number_integer_t) override { return element(); }
  bool number_unsigned(number_unsigned_t) override { return element(); }
  bool number_float(number_float_t, const string_t&) override { return element(); }
  bool string(string_t&) override { return element(); }
  bool binary(binary_t&) override { return element(); }
  bool start_object(std::size_t) override { return open(false); }
  bool start_array(std::size_t) override { return open(true); }
  bool end_object() override { return close(); }
  bool end_array() override { return close(); }
  bool key(string_t& k) override {
    Open& o = open_.back();
    if (!o.keys.insert(k).second) {
      repeated = json_child(o.path, k);
      return false;
    }
    o.key = k;
    return true;
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }

 private:
  struct Open {
    std::string path, key;
    bool array = false;
    size_t index = 0;
    std::unordered_set<std::string> keys;
  };
  std::vector<Open> open_;

  // A scalar needs no path, only its place counted in an array.
  bool element() {
    if (!open_.empty() && open_.back().array) ++open_.back().index;
    return true;
  }
  bool open(bool array) {
    Open o;
    if (!open_.empty()) {
      Open& parent = open_.back();
      o.path = parent.array ? json_index(parent.path, parent.index++) : json_child(parent.path, parent.key);
    }
    o.array = array;
    open_.push_back(std::move(o));
    return true;
  }
  bool close() {
    open_.pop_back();
    return true;
  }
};

}  // namespace

std::optional<std::string> find_repeated_key(const std::string& text) {
  RepeatedKeyFinder finder;
  nlohmann::json::sax_parse(text, &finder);
  return finder.repeated;
}

std::string json_type_name(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::null: return "null";
    case nlohmann::json::value_t::object: return "an object";
    case nlohmann::json::value_t::array: return "an array";
    case nlohmann::json::value_t::string: return "a string";
    case nlohmann::json::value_t::boolean: return "a boolean";
    case nlohmann::json::value_t::number_integer:
    case nlohmann::json::value_t::number_unsigned:
    case nlohmann::json::value_t::number_float: return "a number";
    default: return "an unsupported value";
  }
}

void JsonFields::fail(const std::string& field, const std::string& reason) const {
  throw InputError(file_, field, reason);
}

void JsonFields::expect_object(const nlohmann::json& j, const std::string& path,
                               std::initializer_list<std::string_view> known) const {
  if (!j.is_object()) fail(path, "expected an object, got " + json_type_name(j));
  const std::vector<std::string_view> names(known);
  for (const auto& [key, value] : j.items()) {
    bool found = false;
    for (std::string_view k : names) found = found || k == key;
    if (!found) {
      std::string list;
      for (std::string_view k : names) list += (list.empty() ? "`" : ", `") + std::string(k) + "`";
      const std::string hint = did_you_mean(key, names);
      fail(json_child(path, key),
           "unknown key `" + key + "`" + (hint.empty() ? "; known keys: " + list : hint));
    }
  }
}

const nlohmann::json* JsonFields::find(const nlohmann::json& obj, std::string_view key) {
  const auto it = obj.find(key);
  return it == obj.end() ? nullptr : &*it;
}

const nlohmann::json& JsonFields::require(const nlohmann::json& obj, const std::string& path,
                                          std::string_view key) const {
  const nlohmann::json* v = find(obj, key);
  if (!v) fail(json_child(path, key), "required field is missing");
  return *v;
}

double JsonFields::number(const nlohmann::json& j, const std::string& path) const {
  if (!j.is_number()) fail(path, "expected a number, got " + json_type_name(j));
  const double v = j.get<double>();
  if (!std::isfinite(v)) fail(path, "number is not finite");
  // Scene values are stored as 32-bit floats: a finite JSON number beyond their range would
  // become infinite, and a tiny one zero, past every range check made here on the double.
  if (std::abs(v) > double(std::numeric_limits<float>::max()))
    fail(path, "number " + fmt(v) + " is beyond a 32-bit float's range (about 3.4e38)");
  if (v != 0.0 && static_cast<float>(v) == 0.0f)
    fail(path, "number " + fmt(v) + " is too small for a 32-bit float, where it would be 0");
  return v;
}

double JsonFields::number_in(const nlohmann::json& j, const std::string& path, double lo, double hi,
                             bool lo_open, bool hi_open) const {
  const double v = number(j, path);
  const bool ok = (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  if (!ok)
    fail(path, "must be in " + std::string(lo_open ? "(" : "[") + fmt(lo) + ", " + fmt(hi) +
                   (hi_open ? ")" : "]") + ", got " + fmt(v));
  return v;
}

long long JsonFields::integer(const nlohmann::json& j, const std::string& path, long long lo,
                              long long hi) const {
  const double v = number(j, path);
  if (v != std::floor(v)) fail(path, "expected a whole number, got " + fmt(v));
  if (v < static_cast<double>(lo) || v > static_cast<double>(hi))
    fail(path, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + fmt(v));
  return static_cast<long long>(v);
}

bool JsonFields::boolean(const nlohmann::json& j, const std::string& path) const {
  if (!j.is_boolean()) fail(path, "expected true or false, got " + json_type_name(j));
  return j.get<bool>();
}

std::string JsonFields::string(const nlohmann::json& j, const std::string& path) const {
  if (!j.is_string()) fail(path, "expected a string, got " + json_type_name(j));
  return j.get<std::string>();
}

std::vector<double> JsonFields::numbers(const nlohmann::json& j, const std::string& path,
                                        size_t min_size, size_t max_size) const {
  const std::string want = min_size == max_size
                               ? std::to_string(min_size)
                               : std::to_string(min_size) + " to " + std::to_string(max_size);
  if (!j.is_array()) fail(path, "expected an array of " + want + " numbers, got " + json_type_name(j));
  if (j.size() < min_size || j.size() > max_size)
    fail(path, "expected " + want + " numbers, got " + std::to_string(j.size()));
  std::vector<double> out;
  for (size_t i = 0; i < j.size(); ++i) out.push_back(number(j[i], json_index(path, i)));
  return out;
}

glm::vec3 JsonFields::vec3(const nlohmann::json& j, const std::string& path) const {
  const auto v = numbers(j, path, 3, 3);
  return glm::vec3(v[0], v[1], v[2]);
}

glm::vec3 JsonFields::vec3_in(const nlohmann::json& j, const std::string& path, double lo, double hi) const {
  if (!j.is_array() || j.size() != 3) (void)numbers(j, path, 3, 3);  // reports shape errors
  glm::vec3 out;
  for (int k = 0; k < 3; ++k) out[k] = static_cast<float>(number_in(j[k], json_index(path, k), lo, hi));
  return out;
}

glm::dvec3 JsonFields::unit_direction(const nlohmann::json& j, const std::string& path) const {
  const auto v = numbers(j, path, 3, 3);
  const glm::dvec3 d(v[0], v[1], v[2]);
  const double len = glm::length(d);
  if (len == 0.0) fail(path, "direction must be non-zero");
  if (!(len > 1e-6))
    fail(path, "direction must have a length above 1e-06 (it is normalised, and a shorter one would be mostly "
               "rounding), got length " + fmt(len));
  return d / len;
}

}  // namespace pelt::io
