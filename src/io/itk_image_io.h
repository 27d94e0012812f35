// NRRD, NIfTI, MetaImage and VTK legacy files through ITK's ImageIO (no ITK type in this
// header; itk_image_io.cpp is one of the sources that include ITK).
#pragma once

#include <string>

#include "load_volume.h"

namespace snert::detail {

// Reads a volume file through the ImageIO that ITK's factory picks for it. snert's own checks
// run first (nrrd.h, metaimage.h, vtk_legacy.h, then the grid's memory), because ITK would
// allocate whatever the header claims and zero-fill what is missing; single-file NIfTI takes
// its samples from snert's own reader (nifti.h) and only its geometry from ITK. Throws
// std::runtime_error "<path>: not a volume format snert reads ..." when no ImageIO can read
// the file. open_volume (load_volume.h) has already checked that the file exists, is not
// empty and, when named .gz, is gzip.
LoadedVolume open_with_image_io(const std::string& path, const LoadOptions& options);

} // namespace snert::detail
