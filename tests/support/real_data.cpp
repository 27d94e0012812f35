#include "support/real_data.h"

#include <filesystem>

namespace snert::test {

const std::string& data_dir() {
    static const std::string dir = SNERT_DATA_DIR;
    return dir;
}

std::string data_file(const std::string& relative) {
    return data_dir() + "/" + relative;
}

bool have_data() {
    return std::filesystem::is_directory(data_dir());
}

} // namespace snert::test
