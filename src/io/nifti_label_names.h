// Label names a NIfTI-1 file carries in its header extensions: the Caret / GIFTI label table
// (ecode 0 or 30 with <Label Key="5" ...>liver</Label> entries) that TotalSegmentator and
// Connectome Workbench write. Anything else (no extension, another format, NIfTI-2, a damaged
// or truncated extension) gives an empty map; this reader never throws.
//
// Bounded: at most kMaxNiftiExtensionBytes of extension data are read (gzip inflated through
// zlib), whatever vox_offset or esize claim.
#pragma once

#include <cstddef>
#include <map>
#include <string>

namespace snert {

inline constexpr std::size_t kMaxNiftiExtensionBytes = 16u << 20; // 16 MiB

// label value -> name, from the extensions of `path` (.nii, .nii.gz or an Analyze-style .hdr).
std::map<int, std::string> nifti_label_names(const std::string& path);

// The label table of an XML text (exposed for tests): every <Label Key="N" ...>NAME</Label>,
// NAME either plain text (with &amp; &lt; &gt; &quot; &apos; decoded) or a CDATA section.
std::map<int, std::string> label_names_from_xml(const std::string& xml);

} // namespace snert
