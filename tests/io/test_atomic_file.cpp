// check_writable (io/atomic_file.h): output paths are checked before the work that fills them.
#include <gtest/gtest.h>

#include <filesystem>

#include "io/atomic_file.h"
#include "support/expect_error.h"
#include "support/temp_folder.h"

namespace snert {
namespace {

using test::expect_error;

TEST(CheckWritable, AcceptsNewAndExistingFilesInAFolder) {
    test::TempFolder folder;
    EXPECT_NO_THROW(check_writable(folder.file("new.stl")));
    test::write_text(folder.file("old.json"), "{}");
    EXPECT_NO_THROW(check_writable(folder.file("old.json")));
    EXPECT_TRUE(std::filesystem::exists(folder.file("old.json")));
    EXPECT_FALSE(std::filesystem::exists(folder.file("new.stl"))); // nothing created
}

TEST(CheckWritable, RefusesMissingFoldersFilesAsFoldersAndFolders) {
    test::TempFolder folder;
    const std::string missing = folder.file("no-dir/m.stl");
    expect_error<std::runtime_error>([&] { check_writable(missing); }, {missing, "does not exist"});
    test::write_text(folder.file("plain"), "x");
    const std::string under_file = folder.file("plain/m.stl");
    expect_error<std::runtime_error>([&] { check_writable(under_file); },
                                     {under_file, "not a folder"});
    std::filesystem::create_directory(folder.file("sub.png"));
    expect_error<std::runtime_error>([&] { check_writable(folder.file("sub.png")); },
                                     {"is a folder"});
    expect_error<std::runtime_error>([&] { check_writable(""); }, {"empty"});
}

} // namespace
} // namespace snert
