// SPDX-License-Identifier: GPL-3.0-or-later
// json_read.hpp -- internal: the strict typed readers of law_json.cpp, for the other file formats
// (scene.cpp). Every reader throws InputError naming the JSON path (errors.hpp).
#pragma once

#include "exact/matrix.hpp"

#include <nlohmann/json.hpp>

#include <initializer_list>
#include <string>

namespace impactcert::json_read {

using ReadJson = nlohmann::json;

ReadJson parse_syntax(const std::string& text); // NUL bytes, duplicate keys, numbers: as law files
// Unknown keys are errors except `note` and `description` (free text).
void expect_object(const ReadJson& j, const std::string& path, std::initializer_list<const char*> allowed,
                   std::initializer_list<const char*> required);
const ReadJson& expect_array(const ReadJson& j, const std::string& path);
std::string get_string(const ReadJson& j, const std::string& path);
Rational get_rational(const ReadJson& j, const std::string& path);
Vector get_vector(const ReadJson& j, const std::string& path);

} // namespace impactcert::json_read
