#pragma once
// Metric paths into summary.json: keys joined by dots; a list element by index (`bodies.0`,
// `velocity[2]`) or, for a list of objects, by its "name" (`bodies.disc.fragments`,
// `contact.body_motion.sphere.velocity[2]`).
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace ckpd::sweep {

// Splits `a.b[2].c` into {a, b, 2, c}; throws std::invalid_argument for an empty part or a
// bracket that is not `[digits]`.
std::vector<std::string> split_json_path(const std::string& path);

// The value at `path`, or nullopt with `missing` set to the part that was not found.
std::optional<nlohmann::json> find_json(const nlohmann::json& root, const std::string& path,
                                        std::string& missing);

// A metric value for a CSV cell: numbers in full precision, strings bare, anything else as
// compact JSON.
std::string json_cell(const nlohmann::json& value);

}  // namespace ckpd::sweep
