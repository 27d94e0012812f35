// ITK's component types and messages, translated for snert's errors.
#include "itk_support.h"

#include <cctype>
#include <stdexcept>

namespace snert::detail {

// ITK messages span lines and name source files and object addresses; keep what they say.
std::string one_line(const std::string& text) {
    std::string cleaned;
    for (std::size_t pos = 0; pos < text.size();) {
        for (const std::string marker : {"ITK ERROR: ", "itk::ERROR: "}) {
            if (text.compare(pos, marker.size(), marker) != 0) continue;
            const std::size_t open = text.find("(0x", pos + marker.size());
            const std::size_t close = open == std::string::npos ? open : text.find("):", open);
            if (close != std::string::npos && close - pos < 100) {
                pos = close + 2;
                break;
            }
        }
        if (pos < text.size()) cleaned += text[pos++];
    }
    std::string folded;
    for (char c : cleaned) {
        const bool space = std::isspace(static_cast<unsigned char>(c)) != 0;
        if (space && (folded.empty() || folded.back() == ' ')) continue;
        folded += space ? ' ' : c;
    }
    while (!folded.empty() && folded.back() == ' ') folded.pop_back();
    if (folded.size() > 400) folded = folded.substr(0, 397) + "...";
    return folded;
}

[[noreturn]] void throw_itk(const std::string& path, const itk::ExceptionObject& error) {
    throw std::runtime_error(path + ": " + one_line(error.GetDescription()));
}

std::optional<ScalarType> scalar_type_of(itk::IOComponentEnum component) {
    using C = itk::IOComponentEnum;
    switch (component) {
    case C::UCHAR:
        return ScalarType::UInt8;
    case C::CHAR:
        return ScalarType::Int8;
    case C::USHORT:
        return ScalarType::UInt16;
    case C::SHORT:
        return ScalarType::Int16;
    case C::UINT:
        return ScalarType::UInt32;
    case C::INT:
        return ScalarType::Int32;
    case C::ULONG:
        return sizeof(unsigned long) == 8 ? ScalarType::UInt64 : ScalarType::UInt32;
    case C::LONG:
        return sizeof(long) == 8 ? ScalarType::Int64 : ScalarType::Int32;
    case C::ULONGLONG:
        return ScalarType::UInt64;
    case C::LONGLONG:
        return ScalarType::Int64;
    case C::FLOAT:
        return ScalarType::Float32;
    case C::DOUBLE:
        return ScalarType::Float64;
    default:
        return std::nullopt;
    }
}

} // namespace snert::detail
