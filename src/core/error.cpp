#include "inhap/core/error.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>

namespace inhap {

namespace {
std::string format_parse(const std::string& file, std::size_t line, std::string_view message) {
  if (line == 0) return fmt::format("{}: {}", file, message);
  return fmt::format("{}:{}: {}", file, line, message);
}
}  // namespace

ParseError::ParseError(std::string file, std::size_t line, std::string_view message)
    : Error(format_parse(file, line, message)), file_(std::move(file)), line_(line) {}

IoError::IoError(const std::string& file, std::string_view message)
    : Error(errno != 0 ? fmt::format("{}: {} ({})", file, message, std::strerror(errno))
                       : fmt::format("{}: {}", file, message)) {}

std::string quote_token(std::string_view token, std::size_t max_len) {
  std::string out;
  for (char c : token.substr(0, max_len)) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      out += fmt::format("\\x{:02x}", static_cast<unsigned char>(c));
    else
      out += c;
  }
  if (token.size() > max_len) out += "...";
  return "'" + out + "'";
}

}  // namespace inhap
