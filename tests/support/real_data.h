// The shared real volumes (CT, MRI, label maps): their folder, set at configure time
// (SNERT_DATA_DIR, by default ../shared/data next to the checkout). Tests that need them skip,
// saying why, when the folder is absent.
#pragma once

#include <string>

#include <gtest/gtest.h>

namespace snert::test {

// The folder of the real volumes, without a trailing slash.
const std::string& data_dir();
// `relative` inside that folder.
std::string data_file(const std::string& relative);
// Whether the folder exists.
bool have_data();

} // namespace snert::test

// Skips the current test, saying where the volumes were looked for, when they are absent.
#define SNERT_REQUIRE_DATA()                                                                       \
    if (!::snert::test::have_data())                                                               \
    GTEST_SKIP() << "test volumes not found in " << ::snert::test::data_dir()                      \
                 << " (set SNERT_DATA_DIR)"
