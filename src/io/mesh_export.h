// One method's mesh written to a file as `snert export` and the app's File > Export meshes
// write it: the format from the extension (mesh_io.h), the surface named after the method, and
// for VTK the distance of each triangle to the accuracy reference of the source at `iso` (the
// per-triangle face-centre accuracy, in voxels) beside its quality and angles.
#pragma once

#include <string>

#include "core/mesh.h"
#include "core/names.h"
#include "mesh_io.h"
#include "source.h"

namespace snert {

// `mesh` in world units, made from `source` at `iso`. Throws as write_mesh does.
void export_mesh(const Mesh& mesh, Method method, const Source& source, float iso,
                 const std::string& path, AbaqusElement abaqus_element = AbaqusElement::S3);

} // namespace snert
