// A small command-line parser for the subcommands: `--name value` options, `--flag` switches and
// positional arguments. Anything unexpected is a UsageError, which main turns into exit code 2.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace snert::cli {

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

class Args {
  public:
    // `options` take a value, `switches` do not. Throws UsageError for an unknown --name or a
    // missing value.
    Args(const std::vector<std::string>& argv, const std::set<std::string>& options,
         const std::set<std::string>& switches);

    const std::vector<std::string>& positional() const { return positional_; }
    bool has(const std::string& name) const { return values_.count(name) != 0; }
    std::optional<std::string> value(const std::string& name) const;
    std::string value_or(const std::string& name, const std::string& fallback) const;
    bool flag(const std::string& name) const { return switches_.count(name) != 0; }

    // Typed values; UsageError naming the option when the text is not a number in [lo, hi].
    int integer(const std::string& name, int fallback, int lo, int hi) const;
    float number(const std::string& name, float fallback) const;
    std::optional<float> number(const std::string& name) const;
    // One of `choices`, or UsageError listing them.
    std::string choice(const std::string& name, const std::string& fallback,
                       const std::vector<std::string>& choices) const;

  private:
    std::vector<std::string> positional_;
    std::map<std::string, std::string> values_;
    std::set<std::string> switches_;
};

// Splits "a,b,c" into parts.
std::vector<std::string> split(const std::string& text, char separator);

} // namespace snert::cli
