// Parsers for the scene blocks whose parameter structs live in other areas: an object's
// `fur` block (fur/fur_params.h) and a material's `skin` block (shading/skin_params.h).
// Internal to pelt_io. Both read every key with its JSON type checked here, then run the
// owning area's validate() and report its first error under the block's path.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "fur/fur_params.h"
#include "shading/skin_params.h"
#include "tools/io/json_fields.h"

namespace pelt::io::detail {

fur::FurParams parse_fur_block(const JsonFields& js, const nlohmann::json& j, const std::string& path);
shading::SkinParams parse_skin_block(const JsonFields& js, const nlohmann::json& j,
                                     const std::string& path);

}  // namespace pelt::io::detail
