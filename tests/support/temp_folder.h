// A fresh folder under the system's temporary directory for one test, removed with everything
// in it when the test ends; and small helpers to write and read files there.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace snert::test {

class TempFolder {
  public:
    // A new, empty folder named `<prefix>-XXXXXX` (mkdtemp): tests running in parallel never
    // share one.
    explicit TempFolder(const std::string& prefix = "snert-test");
    ~TempFolder();
    TempFolder(const TempFolder&) = delete;
    TempFolder& operator=(const TempFolder&) = delete;

    const std::filesystem::path& path() const { return path_; }
    // The path of `name` inside the folder, as a string (the file need not exist).
    std::string file(const std::string& name) const;

  private:
    std::filesystem::path path_;
};

// Writes `text` (or `bytes`) to `path`, replacing the file; throws std::runtime_error on failure.
void write_text(const std::filesystem::path& path, std::string_view text);
void write_bytes(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes);
// The whole file; throws std::runtime_error when it cannot be opened.
std::string read_text(const std::filesystem::path& path);

} // namespace snert::test
