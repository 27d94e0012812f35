// Phantoms: synthetic float distance maps like the paper's test objects (section 3), each with
// its exact reference surface so accuracy can be measured analytically.
//
// Every phantom is a signed distance in voxel units, positive inside the object, segmented
// with I >= iso at iso 0 (0.5 for the binary sphere). Names as on the command line:
//   plane        plane with normal (1, 2, 3) through the grid centre
//   sphere       sphere of radius 0.35 * size around the grid centre
//   two-spheres  union of two partly overlapping spheres
//   torus        torus around the z axis
//   noisy-sphere the sphere plus seeded Gaussian noise (sigma 0.25); reference: the clean sphere
//   binary-sphere the sphere as 0/1 values only (no useful grey), iso 0.5
// Teaching phantoms: each shows one idea on a few cells, on a fixed small grid (the size
// argument does not apply), so the whole net fits on one screen and every node can be clicked:
//   tilted-plane  plane with normal (1, 2, 3) on a 10^3 grid, passing between the samples
//   small-sphere  sphere of radius 4 on a 12^3 grid
//   thin-plate    a square plate one voxel thick (only its middle samples inside), 12 x 12 x 7
//   crease        two spheres of radius 3.5 overlapping, meeting at a crease, 15 x 11 x 11
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "volume.h"

namespace snert {

struct Phantom {
    std::string name;
    Volume volume;
    float iso = 0.0f;
    // Unsigned distance (voxel units, index space) from a point to the exact reference surface.
    std::function<float(glm::vec3)> reference_distance;
    // Volume enclosed by the reference surface (voxels^3, index space), for volume error.
    double reference_volume = 0.0;
};

// The phantom names accepted by make_phantom, in menu order (the teaching phantoms last).
std::vector<std::string> phantom_names();
// The teaching phantoms among them: fixed small grids whatever the size asked for.
std::vector<std::string> teaching_phantom_names();
bool is_teaching_phantom(std::string_view name);

// Builds phantom `name` on a size^3 grid (a teaching phantom on its own grid). Throws
// std::invalid_argument for an unknown name or a size outside [8, 1024].
Phantom make_phantom(std::string_view name, int size = 64, unsigned seed = 1);

// Plane with any normal through `point` (index space), for tests.
Phantom make_plane_phantom(int size, glm::vec3 normal, glm::vec3 point);

// Splits "phantom:NAME" into NAME; returns an empty view when `spec` is not a phantom spec.
std::string_view phantom_spec_name(std::string_view spec);

} // namespace snert
