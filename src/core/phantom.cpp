// Synthetic distance-map phantoms with analytic reference surfaces (paper section 3).
#include "phantom.h"

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace snert {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Fills a size^3 volume with f(index point), evaluated in double for exact zeros on planes.
template <class F> Volume fill(int size, F f) {
    Volume v = make_volume(glm::ivec3(size));
    for (int z = 0; z < size; ++z)
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) v.samples[v.index(x, y, z)] = float(f(x, y, z));
    return v;
}

glm::dvec3 centre_of(int size) {
    return glm::dvec3((size - 1) * 0.5);
}

Phantom sphere(int size, std::string name) {
    const glm::dvec3 c = centre_of(size);
    const double r = 0.35 * size;
    Phantom p;
    p.name = std::move(name);
    p.volume =
        fill(size, [&](int x, int y, int z) { return r - glm::length(glm::dvec3(x, y, z) - c); });
    p.reference_distance = [c, r](glm::vec3 q) {
        return float(std::abs(glm::length(glm::dvec3(q) - c) - r));
    };
    p.reference_volume = 4.0 / 3.0 * kPi * r * r * r;
    return p;
}

Phantom two_spheres(int size) {
    // Two spheres whose centres are 0.9 of a radius apart along a diagonal: partly overlapping,
    // with a crease where they meet (paper figure 6).
    const glm::dvec3 c = centre_of(size);
    const double r = 0.26 * size;
    const glm::dvec3 axis = glm::normalize(glm::dvec3(1.0, 0.6, 0.3));
    const glm::dvec3 c1 = c - axis * (0.45 * r), c2 = c + axis * (0.45 * r);
    auto signed_distance = [=](glm::dvec3 q) {
        return std::max(r - glm::length(q - c1), r - glm::length(q - c2));
    };
    Phantom p;
    p.name = "two-spheres";
    p.volume = fill(size, [&](int x, int y, int z) { return signed_distance({x, y, z}); });
    // max() of two distance fields is the exact distance outside the union and near the surface
    // except right at the crease, where it is a close upper bound; good enough for a reference.
    p.reference_distance = [=](glm::vec3 q) {
        const glm::dvec3 d(q);
        const double d1 = glm::length(d - c1) - r, d2 = glm::length(d - c2) - r;
        // Distance to the union's boundary: the nearer sphere surface that is not inside the other.
        double best = 1e30;
        for (int s = 0; s < 2; ++s) {
            const glm::dvec3 cs = s == 0 ? c1 : c2, co = s == 0 ? c2 : c1;
            const glm::dvec3 dir = glm::length(d - cs) > 0 ? glm::normalize(d - cs) : axis;
            const glm::dvec3 foot = cs + dir * r;
            if (glm::length(foot - co) >= r) best = std::min(best, std::abs(s == 0 ? d1 : d2));
        }
        // The crease circle, where the two surfaces meet.
        const double half = 0.45 * r;
        const double ring = std::sqrt(std::max(0.0, r * r - half * half));
        const glm::dvec3 rel = d - c;
        const double along = glm::dot(rel, axis);
        const double radial = glm::length(rel - axis * along);
        best = std::min(best, std::hypot(along, radial - ring));
        return float(best);
    };
    const double h = r - 0.45 * r; // cap height of each sphere inside the other
    const double cap = kPi * h * h * (3.0 * r - h) / 3.0;
    p.reference_volume = 2.0 * (4.0 / 3.0 * kPi * r * r * r) - 2.0 * cap;
    return p;
}

Phantom torus(int size) {
    const glm::dvec3 c = centre_of(size);
    const double major = 0.28 * size, minor = 0.12 * size;
    auto distance = [=](glm::dvec3 q) {
        const glm::dvec3 d = q - c;
        return std::hypot(std::hypot(d.x, d.y) - major, d.z) - minor;
    };
    Phantom p;
    p.name = "torus";
    p.volume = fill(size, [&](int x, int y, int z) { return -distance({x, y, z}); });
    p.reference_distance = [=](glm::vec3 q) { return float(std::abs(distance(glm::dvec3(q)))); };
    p.reference_volume = 2.0 * kPi * kPi * major * minor * minor;
    return p;
}

// Signed distance to an axis-aligned box (positive inside): exact inside and outside.
double box_distance(glm::dvec3 q, glm::dvec3 centre, glm::dvec3 half) {
    const glm::dvec3 d = glm::abs(q - centre) - half;
    const double outside = glm::length(glm::max(d, glm::dvec3(0.0)));
    const double inside = std::min(std::max({d.x, d.y, d.z}), 0.0);
    return -(outside + inside);
}

// Fills a dims grid with f(index point).
template <class F> Volume fill_dims(glm::ivec3 dims, F f) {
    Volume v = make_volume(dims);
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x)
                v.samples[v.index(x, y, z)] = float(f(glm::dvec3(x, y, z)));
    return v;
}

Phantom small_sphere() {
    // Radius 4 around a centre off the sample grid, so no sample lies on the surface and the
    // cells around it differ (the paper's Fig. 2 on a few cells).
    const glm::dvec3 c(5.6, 5.45, 5.3);
    const double r = 4.0;
    Phantom p;
    p.name = "small-sphere";
    p.volume = fill_dims(glm::ivec3(12), [&](glm::dvec3 q) { return r - glm::length(q - c); });
    p.reference_distance = [c, r](glm::vec3 q) {
        return float(std::abs(glm::length(glm::dvec3(q) - c) - r));
    };
    p.reference_volume = 4.0 / 3.0 * kPi * r * r * r;
    return p;
}

Phantom thin_plate() {
    // Only the samples of the plane z = 3 are inside (value 0.5, their neighbours -0.5): the
    // net must keep the plate's two sides apart although both run through the same cells.
    const glm::dvec3 c(5.5, 5.5, 3.0), half(3.7, 3.7, 0.5);
    Phantom p;
    p.name = "thin-plate";
    p.volume =
        fill_dims(glm::ivec3(12, 12, 7), [&](glm::dvec3 q) { return box_distance(q, c, half); });
    p.reference_distance = [c, half](glm::vec3 q) {
        return float(std::abs(box_distance(glm::dvec3(q), c, half)));
    };
    p.reference_volume = 8.0 * half.x * half.y * half.z;
    return p;
}

Phantom crease() {
    // Two spheres of radius 3.5 whose centres are 4.6 apart: they overlap and meet at a
    // circular crease (the paper's Fig. 6 on a few cells).
    const double r = 3.5;
    const glm::dvec3 c1(5.0, 5.2, 5.1), c2(9.6, 5.2, 5.1);
    auto signed_distance = [=](glm::dvec3 q) {
        return std::max(r - glm::length(q - c1), r - glm::length(q - c2));
    };
    Phantom p;
    p.name = "crease";
    p.volume = fill_dims(glm::ivec3(15, 11, 11), signed_distance);
    const glm::dvec3 axis = glm::normalize(c2 - c1), mid = 0.5 * (c1 + c2);
    const double half = 0.5 * glm::length(c2 - c1);
    const double ring = std::sqrt(r * r - half * half);
    p.reference_distance = [=](glm::vec3 q) {
        const glm::dvec3 d(q);
        // The union's boundary: each sphere's surface outside the other, and the crease circle.
        double best = 1e30;
        for (int s = 0; s < 2; ++s) {
            const glm::dvec3 cs = s == 0 ? c1 : c2, co = s == 0 ? c2 : c1;
            const glm::dvec3 dir = glm::length(d - cs) > 0 ? glm::normalize(d - cs) : axis;
            if (glm::length(cs + dir * r - co) >= r)
                best = std::min(best, std::abs(glm::length(d - cs) - r));
        }
        const double along = glm::dot(d - mid, axis);
        const double radial = glm::length(d - mid - axis * along);
        return float(std::min(best, std::hypot(along, radial - ring)));
    };
    const double h = r - half; // cap height of each sphere inside the other
    const double cap = kPi * h * h * (3.0 * r - h) / 3.0;
    p.reference_volume = 2.0 * (4.0 / 3.0 * kPi * r * r * r) - 2.0 * cap;
    return p;
}

} // namespace

Phantom make_plane_phantom(int size, glm::vec3 normal, glm::vec3 point) {
    const glm::dvec3 n(normal), o(point);
    const double length = glm::length(n);
    if (!(length > 0)) throw std::invalid_argument("plane normal must not be zero");
    // Unnormalised dot product first: integer normals through half-integer centres then give
    // exact zeros on the samples the plane passes through.
    const double offset = glm::dot(n, o);
    Phantom p;
    p.name = "plane";
    p.volume = fill(size, [&](int x, int y, int z) {
        return -(glm::dot(n, glm::dvec3(x, y, z)) - offset) / length;
    });
    p.reference_distance = [n, offset, length](glm::vec3 q) {
        return float(std::abs(glm::dot(n, glm::dvec3(q)) - offset) / length);
    };
    p.reference_volume = 0.0; // not closed
    return p;
}

std::vector<std::string> teaching_phantom_names() {
    return {"tilted-plane", "small-sphere", "thin-plate", "crease"};
}

bool is_teaching_phantom(std::string_view name) {
    for (const std::string& n : teaching_phantom_names())
        if (n == name) return true;
    return false;
}

std::vector<std::string> phantom_names() {
    std::vector<std::string> names = {"plane", "sphere",       "two-spheres",
                                      "torus", "noisy-sphere", "binary-sphere"};
    for (std::string& n : teaching_phantom_names()) names.push_back(std::move(n));
    return names;
}

Phantom make_phantom(std::string_view name, int size, unsigned seed) {
    if (size < 8 || size > 1024)
        throw std::invalid_argument("phantom size " + std::to_string(size) + " is outside 8..1024");
    if (name == "tilted-plane") {
        // Through a point off the samples, so every cell it crosses is cut in a general way.
        Phantom p = make_plane_phantom(10, {1, 2, 3}, glm::vec3(4.3f, 4.6f, 4.4f));
        p.name = "tilted-plane";
        return p;
    }
    if (name == "small-sphere") return small_sphere();
    if (name == "thin-plate") return thin_plate();
    if (name == "crease") return crease();
    if (name == "plane") {
        const float c = float(size - 1) * 0.5f;
        return make_plane_phantom(size, {1, 2, 3}, glm::vec3(c));
    }
    if (name == "sphere") return sphere(size, "sphere");
    if (name == "two-spheres") return two_spheres(size);
    if (name == "torus") return torus(size);
    if (name == "noisy-sphere") {
        Phantom p = sphere(size, "noisy-sphere");
        std::mt19937 rng(seed);
        std::normal_distribution<float> noise(0.0f, 0.25f);
        for (float& v : p.volume.samples) v += noise(rng);
        return p;
    }
    if (name == "binary-sphere") {
        Phantom p = sphere(size, "binary-sphere");
        for (float& v : p.volume.samples) v = v >= 0.0f ? 1.0f : 0.0f;
        p.iso = 0.5f;
        return p;
    }
    std::string known;
    for (const auto& n : phantom_names()) known += (known.empty() ? "" : ", ") + n;
    throw std::invalid_argument("unknown phantom '" + std::string(name) + "' (known: " + known +
                                ")");
}

std::string_view phantom_spec_name(std::string_view spec) {
    constexpr std::string_view prefix = "phantom:";
    if (spec.substr(0, prefix.size()) != prefix) return {};
    return spec.substr(prefix.size());
}

} // namespace snert
