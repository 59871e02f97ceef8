// Typed, located reads from a parsed JSON document: every failure becomes an InputError
// naming the file, the JSON field path (`objects[1].transform.scale`) and the reason.
#pragma once

#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

namespace pelt::io {

// "a.b" / "b" when the parent path is empty.
std::string json_child(const std::string& path, std::string_view key);
// "a[3]".
std::string json_index(const std::string& path, size_t i);
// The first key given twice in one object of `text` (well-formed JSON), as the field path of
// its second appearance (`image.width`), or nullopt. nlohmann::json keeps a repeated key's
// last value without a word, so a copy-pasted key would silently override the one the user
// reads first; the scene parser refuses such a file instead.
std::optional<std::string> find_repeated_key(const std::string& text);
// "a number", "a string", "an array", ... for "expected X, got Y" messages.
std::string json_type_name(const nlohmann::json& j);

class JsonFields {
 public:
  explicit JsonFields(std::string file) : file_(std::move(file)) {}
  const std::string& file() const { return file_; }

  [[noreturn]] void fail(const std::string& field, const std::string& reason) const;

  // `j` must be an object whose keys are all in `known`; an unknown key is an error with
  // the nearest known key suggested.
  void expect_object(const nlohmann::json& j, const std::string& path,
                     std::initializer_list<std::string_view> known) const;
  // The member `key` of object `obj`, or nullptr.
  static const nlohmann::json* find(const nlohmann::json& obj, std::string_view key);
  // As find(), but a missing member is an error ("required field is missing").
  const nlohmann::json& require(const nlohmann::json& obj, const std::string& path,
                                std::string_view key) const;

  // A finite number (JSON integers accepted).
  double number(const nlohmann::json& j, const std::string& path) const;
  // A finite number in [lo, hi], with open ends where asked; the message shows the range.
  double number_in(const nlohmann::json& j, const std::string& path, double lo, double hi,
                   bool lo_open = false, bool hi_open = false) const;
  // A whole number in [lo, hi] (1.0 is accepted as 1; 1.5 is not).
  long long integer(const nlohmann::json& j, const std::string& path, long long lo, long long hi) const;
  bool boolean(const nlohmann::json& j, const std::string& path) const;
  std::string string(const nlohmann::json& j, const std::string& path) const;
  // An array of `min_size`..`max_size` finite numbers.
  std::vector<double> numbers(const nlohmann::json& j, const std::string& path, size_t min_size,
                              size_t max_size) const;
  glm::vec3 vec3(const nlohmann::json& j, const std::string& path) const;
  // A vec3 with every component in [lo, hi].
  glm::vec3 vec3_in(const nlohmann::json& j, const std::string& path, double lo, double hi) const;
  // A vec3 longer than 1e-6 (the bound fur::FurParams' directions have), returned normalised
  // in double: a shorter one would be mostly rounding once normalised.
  glm::dvec3 unit_direction(const nlohmann::json& j, const std::string& path) const;
  glm::vec3 direction(const nlohmann::json& j, const std::string& path) const {
    return glm::vec3(unit_direction(j, path));
  }

 private:
  std::string file_;
};

}  // namespace pelt::io
