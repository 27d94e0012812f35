// What the two ITK readers share (itk_image_io.cpp, dicom_series.cpp): ITK's component types
// as snert's ScalarType, and ITK's messages as one line. This header includes ITK: only
// sources compiled with ITK's include folders (src/io/CMakeLists.txt) may include it.
#pragma once

#include <optional>
#include <string>

#include <itkMacro.h>
#include <itkImageIOBase.h>

#include "sample_conversion.h"

namespace snert::detail {

// An ITK message (which spans lines and names source files and object addresses) as one
// line of at most 400 characters: each "itk::ERROR: ClassName(0x55d0...): " prefix dropped,
// white space folded.
std::string one_line(const std::string& text);

// Throws std::runtime_error "<path>: <the exception's description, one_line>".
[[noreturn]] void throw_itk(const std::string& path, const itk::ExceptionObject& error);

// The ScalarType of an ITK component type; empty for types snert does not read (complex,
// unknown). LONG / ULONG follow the platform's long.
std::optional<ScalarType> scalar_type_of(itk::IOComponentEnum component);

} // namespace snert::detail
