// snert_snapshot_compare: compares a rendered PNG with its golden copy.
//
//   snert_snapshot_compare GOLDEN ACTUAL DIFF [--tolerance T] [--max-share S]
//
// A pixel differs when one of its channels differs by more than T (0..255, default 8); the
// test fails when more than the share S of the pixels differ (default 0.002, i.e. 0.2 %).
// On failure the difference image is written to DIFF and the message names ACTUAL and DIFF.
// With SNERT_UPDATE_SNAPSHOTS=1 in the environment ACTUAL is copied over GOLDEN instead
// (regenerating the goldens on purpose; look at them before committing).
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>

#include "render/image.h"

namespace {

struct Options {
    std::string golden, actual, diff;
    int tolerance = 8;
    double max_share = 0.002;
};

Options parse(int argc, char** argv) {
    Options o;
    int positional = 0;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if ((a == "--tolerance" || a == "--max-share") && i + 1 < argc) {
            const std::string v = argv[++i];
            if (a == "--tolerance")
                o.tolerance = std::stoi(v);
            else
                o.max_share = std::stod(v);
        } else if (positional == 0) {
            o.golden = a, ++positional;
        } else if (positional == 1) {
            o.actual = a, ++positional;
        } else if (positional == 2) {
            o.diff = a, ++positional;
        } else {
            throw std::invalid_argument("unexpected argument '" + a + "'");
        }
    }
    if (positional != 3)
        throw std::invalid_argument("usage: snert_snapshot_compare GOLDEN ACTUAL DIFF "
                                    "[--tolerance T] [--max-share S]");
    return o;
}

bool update_requested() {
    const char* value = std::getenv("SNERT_UPDATE_SNAPSHOTS");
    return value != nullptr && std::string(value) == "1";
}

} // namespace

int main(int argc, char** argv) {
    try {
        const Options o = parse(argc, argv);
        namespace fs = std::filesystem;
        if (update_requested()) {
            fs::create_directories(fs::path(o.golden).parent_path());
            fs::copy_file(o.actual, o.golden, fs::copy_options::overwrite_existing);
            std::cout << "updated golden " << o.golden << " from " << o.actual << "\n";
            return 0;
        }
        if (!fs::exists(o.golden)) {
            std::cerr << "no golden image " << o.golden << " (actual: " << o.actual
                      << "); create it with SNERT_UPDATE_SNAPSHOTS=1\n";
            return 1;
        }
        const snert::render::Image golden = snert::render::read_png(o.golden);
        const snert::render::Image actual = snert::render::read_png(o.actual);
        if (golden.width != actual.width || golden.height != actual.height) {
            std::cerr << "size differs: golden " << o.golden << " is " << golden.width << "x"
                      << golden.height << ", actual " << o.actual << " is " << actual.width << "x"
                      << actual.height << "\n";
            return 1;
        }
        const snert::render::ImageComparison c =
            snert::render::compare_images(golden, actual, o.tolerance);
        char summary[160];
        std::snprintf(summary, sizeof summary,
                      "%zu of %zu pixels (%.4f %%) differ by more than %d (allowed %.4f %%; "
                      "largest difference %d)",
                      c.differing, c.pixels, 100.0 * c.share(), o.tolerance, 100.0 * o.max_share,
                      c.largest_difference);
        if (c.share() > o.max_share) {
            snert::render::write_png(o.diff,
                                     snert::render::difference_image(golden, actual, o.tolerance));
            std::cerr << "snapshot differs from " << o.golden << ": " << summary
                      << "\n  actual: " << o.actual << "\n  diff:   " << o.diff
                      << "\n  (if the change is intended: SNERT_UPDATE_SNAPSHOTS=1 ctest -R "
                         "snapshot, then look at the new goldens)\n";
            return 1;
        }
        std::cout << "snapshot matches " << o.golden << ": " << summary << "\n";
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "snert_snapshot_compare: " << e.what() << "\n";
        return 2;
    }
}
