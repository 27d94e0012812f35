// Mesh metrics: triangle quality, smoothness, accuracy and topology, as plain structs.
//
// Quality of a triangle, three ways (1 = equilateral, 0 = degenerate):
//   quality        smallest angle / largest angle, the paper's measure (section 3);
//   quality60      smallest angle / 60 degrees;
//   radius_ratio   2 r / R (inradius over circumradius), as in Verdict.
// Smoothness (paper section 3): mean over interior manifold vertices of |2 pi - sum of the
// angles of the incident triangles| (radians; best case 0, a plane).
// Accuracy (paper eq. 7): mean distance of the vertices, and of the face centres, to a reference
// surface, given as a distance function.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "mesh.h"

namespace snert {

struct TriangleShape {
    float quality = 0;       // smallest / largest angle (best 1)
    float quality60 = 0;     // smallest angle / 60 degrees (best 1)
    float radius_ratio = 0;  // 2 r / R (best 1)
    float min_angle = 0;     // degrees
    float area = 0;
};
TriangleShape triangle_shape(glm::vec3 a, glm::vec3 b, glm::vec3 c);

// Per-triangle smallest/largest angle, the quantity the views colour by.
std::vector<float> triangle_quality(const Mesh& mesh);

inline constexpr int kQualityBins = 20;

struct QualityStats {
    double mean = 0, min = 0;                 // smallest / largest angle
    double quality60_mean = 0;
    double radius_ratio_mean = 0;
    double min_angle_min = 0;                 // degrees
    std::size_t degenerate = 0;               // zero-area triangles
    std::array<std::size_t, kQualityBins> histogram{};  // counts over [0, 1], last bin closed
};
QualityStats quality_stats(const Mesh& mesh);

// Mean |2 pi - angle sum| over interior manifold vertices (those whose incident triangles form
// one closed fan). Radians.
double smoothness(const Mesh& mesh);

struct Topology {
    bool watertight = false;  // every edge has exactly two incident triangles
    bool manifold = false;    // ... and every vertex's triangles form a single fan
    bool oriented = false;    // every interior edge is used once in each direction
    long euler = 0;           // V - E + F over referenced vertices
    std::size_t boundary_edges = 0;
    std::size_t nonmanifold_edges = 0;
};
Topology topology(const Mesh& mesh);

double surface_area(const Mesh& mesh);
// Signed enclosed volume (divergence theorem); positive for a closed outward-wound mesh.
double enclosed_volume(const Mesh& mesh);

using DistanceFunction = std::function<float(glm::vec3)>;

struct Accuracy {
    double vertices_mean = 0, vertices_max = 0;
    double faces_mean = 0, faces_max = 0;
};
Accuracy accuracy(const Mesh& mesh, const DistanceFunction& distance);

// Distance from points to a triangle mesh, accelerated by a uniform grid of triangles (never all
// pairs). Build once, query many times; thread-safe queries.
class MeshDistance {
public:
    explicit MeshDistance(const Mesh& reference);
    float operator()(glm::vec3 p) const;

private:
    struct Impl;
    std::shared_ptr<const Impl> impl_;
};

} // namespace snert
