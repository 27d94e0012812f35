#include "args.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace snert::cli {

Args::Args(const std::vector<std::string>& argv, const std::set<std::string>& options,
           const std::set<std::string>& switches) {
    for (std::size_t i = 0; i < argv.size(); ++i) {
        const std::string& a = argv[i];
        if (a.size() > 2 && a.rfind("--", 0) == 0) {
            std::string name = a.substr(2), inline_value;
            const auto eq = name.find('=');
            const bool has_inline = eq != std::string::npos;
            if (has_inline) {
                inline_value = name.substr(eq + 1);
                name = name.substr(0, eq);
            }
            if (switches.count(name) && !has_inline) {
                switches_.insert(name);
            } else if (options.count(name)) {
                if (has_inline) {
                    values_[name] = inline_value;
                } else {
                    if (i + 1 >= argv.size())
                        throw UsageError("option --" + name + " needs a value");
                    values_[name] = argv[++i];
                }
            } else {
                throw UsageError("unknown option --" + name);
            }
        } else {
            positional_.push_back(a);
        }
    }
}

std::optional<std::string> Args::value(const std::string& name) const {
    auto it = values_.find(name);
    if (it == values_.end()) return std::nullopt;
    return it->second;
}

std::string Args::value_or(const std::string& name, const std::string& fallback) const {
    return value(name).value_or(fallback);
}

int Args::integer(const std::string& name, int fallback, int lo, int hi) const {
    auto text = value(name);
    if (!text) return fallback;
    errno = 0;
    char* end = nullptr;
    const long v = std::strtol(text->c_str(), &end, 10);
    if (text->empty() || *end != '\0' || errno != 0 || v < lo || v > hi)
        throw UsageError("--" + name + " must be an integer in " + std::to_string(lo) + ".." +
                         std::to_string(hi) + ", got '" + *text + "'");
    return int(v);
}

std::optional<float> Args::number(const std::string& name) const {
    auto text = value(name);
    if (!text) return std::nullopt;
    char* end = nullptr;
    const float v = std::strtof(text->c_str(), &end);
    if (text->empty() || *end != '\0' || !std::isfinite(v))
        throw UsageError("--" + name + " must be a finite number, got '" + *text + "'");
    return v;
}

float Args::number(const std::string& name, float fallback) const {
    return number(name).value_or(fallback);
}

std::string Args::choice(const std::string& name, const std::string& fallback,
                         const std::vector<std::string>& choices) const {
    std::string v = value_or(name, fallback);
    for (const auto& c : choices)
        if (c == v) return v;
    std::string list;
    for (const auto& c : choices) list += (list.empty() ? "" : "|") + c;
    throw UsageError("--" + name + " must be one of " + list + ", got '" + v + "'");
}

std::vector<std::string> split(const std::string& text, char separator) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    while (true) {
        const auto at = text.find(separator, start);
        parts.push_back(text.substr(start, at - start));
        if (at == std::string::npos) break;
        start = at + 1;
    }
    return parts;
}

} // namespace snert::cli
