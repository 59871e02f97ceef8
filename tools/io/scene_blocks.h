// Parsers for the scene blocks whose parameter structs live in other areas: an object's
// `fur` block (fur/fur_params.h), a material's `skin` block (shading/skin_params.h) and the
// scene's `quality` block (tools/io/quality.h).
// Internal to pelt_io. Both read every key with its JSON type checked here, then run the
// owning area's validate() and report its first error under the block's path.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "fur/fur_params.h"
#include "shading/skin_params.h"
#include "tools/io/quality.h"
#include "tools/io/json_fields.h"

namespace pelt::io::detail {

fur::FurParams parse_fur_block(const JsonFields& js, const nlohmann::json& j, const std::string& path);
shading::SkinParams parse_skin_block(const JsonFields& js, const nlohmann::json& j,
                                     const std::string& path);
// The scene's `quality` block: an optional "preset", then any knob of io::kKnobs on top.
Quality parse_quality_block(const JsonFields& js, const nlohmann::json& j, const std::string& path);

}  // namespace pelt::io::detail
