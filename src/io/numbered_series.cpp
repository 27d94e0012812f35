// Numbered slice series: the runs of digits in a file name, and the names that count on.
#include "numbered_series.h"

#include <algorithm>
#include <cctype>

namespace snert::detail {

std::vector<NumberedName> numbered_name_candidates(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    const std::size_t name_start = slash == std::string::npos ? 0 : slash + 1;
    std::vector<NumberedName> runs; // from the end of the name
    for (std::size_t end = path.size(); end > name_start;) {
        if (!std::isdigit(static_cast<unsigned char>(path[end - 1]))) {
            --end;
            continue;
        }
        std::size_t begin = end;
        while (begin > name_start && std::isdigit(static_cast<unsigned char>(path[begin - 1])))
            --begin;
        const std::string digits = path.substr(begin, end - begin);
        if (digits.size() <= 18) { // keeps number + count inside uint64
            NumberedName name;
            name.prefix = path.substr(0, begin);
            name.suffix = path.substr(end);
            name.number = std::stoull(digits);
            name.width = digits.size() > 1 && digits[0] == '0' ? digits.size() : 0;
            runs.push_back(std::move(name));
        }
        end = begin;
    }
    // The last run before the extension goes first, when the name has one.
    const std::size_t dot = path.find_last_of('.');
    if (dot != std::string::npos && dot > name_start) {
        const auto before_ext = std::find_if(
            runs.begin(), runs.end(), [&](const NumberedName& n) { return n.prefix.size() < dot; });
        if (before_ext != runs.end()) std::rotate(runs.begin(), before_ext, before_ext + 1);
    }
    return runs;
}

std::optional<NumberedName> parse_numbered_name(const std::string& path) {
    auto runs = numbered_name_candidates(path);
    if (runs.empty()) return std::nullopt;
    return runs.front();
}

std::string numbered_path(const NumberedName& name, std::uint64_t number) {
    std::string digits = std::to_string(number);
    if (digits.size() < name.width) digits.insert(0, name.width - digits.size(), '0');
    return name.prefix + digits + name.suffix;
}

} // namespace snert::detail
