#include "inhap/core/error.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>

namespace inhap {

namespace {
// Error messages are one line of bounded length: input quoted in them (a 20 MB JSON string, a
// binary token) is cut and control characters are escaped.
constexpr std::size_t kMaxMessage = 400;

std::string one_line(std::string_view message) {
  std::string out;
  for (char c : message.substr(0, kMaxMessage)) {
    if (c == '\n' || c == '\r' || c == '\t')
      out += ' ';
    else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      out += fmt::format("\\x{:02x}", static_cast<unsigned char>(c));
    else
      out += c;
  }
  if (message.size() > kMaxMessage)
    out += fmt::format("... ({} characters cut)", message.size() - kMaxMessage);
  return out;
}

std::string format_parse(const std::string& file, std::size_t line, std::string_view raw) {
  const std::string message = one_line(raw);
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
