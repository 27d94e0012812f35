#include "support/expect_error.h"

namespace snert::test {

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

void expect_contains(const std::string& message, std::initializer_list<std::string> parts) {
    for (const std::string& part : parts)
        EXPECT_TRUE(contains(message, part)) << "message should say '" << part << "': " << message;
}

} // namespace snert::test
