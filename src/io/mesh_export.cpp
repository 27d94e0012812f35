#include "mesh_export.h"

#include "core/triangle_fields.h"

namespace snert {

void export_mesh(const Mesh& mesh, Method method, const Source& source, float iso,
                 const std::string& path, AbaqusElement abaqus_element) {
    const MeshFormat format = mesh_format_from_path(path);
    MeshWriteOptions options;
    options.name = std::string(name_of(method));
    options.abaqus_element = abaqus_element;
    // Only VTK has a place for it, and it costs a pass of the reference over the triangles.
    if (format == MeshFormat::Vtk && source.volume)
        options.distance =
            centroid_distances(mesh, *source.volume, accuracy_reference(source, iso).distance);
    write_mesh(mesh, path, format, options);
}

} // namespace snert
