// Raw options as people type them: "64,64,93" for the dimensions and "3.2,3.2,1.5" for the
// spacing. The command line (--raw, --raw-spacing) and the app's settings file read and write
// this one form, so a line copied from one works in the other.
#pragma once

#include <string>

#include <glm/glm.hpp>

namespace snert {

// Parse "X,Y,Z" into `dims` (each >= 1) or `spacing` (each positive and finite). Returns an
// empty string on success, else what is wrong in one line (the target is then unchanged).
std::string parse_raw_dims(const std::string& text, glm::ivec3& dims);
std::string parse_raw_spacing(const std::string& text, glm::vec3& spacing);

// "64,64,93"; "3.2,3.2,1.5" (each the shortest text that reads back as the same float).
std::string raw_dims_text(glm::ivec3 dims);
std::string raw_spacing_text(glm::vec3 spacing);

} // namespace snert
