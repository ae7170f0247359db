// inhap errors: every failure on bad input names the file, the line (or record) and what was
// expected, in one line: "FILE:LINE: expected X, got Y".
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace inhap {

/// Base class of every error inhap throws on bad input or bad arguments.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Bad content in a file or stream. what() = "file:line: message" (line omitted when 0).
class ParseError : public Error {
 public:
  ParseError(std::string file, std::size_t line, std::string_view message);
  const std::string& file() const { return file_; }
  std::size_t line() const { return line_; }

 private:
  std::string file_;
  std::size_t line_;
};

/// A file that cannot be opened, read or written. what() = "file: message (strerror)".
class IoError : public Error {
 public:
  IoError(const std::string& file, std::string_view message);
};

/// Shortens a token for error messages ("got 'abc…'").
std::string quote_token(std::string_view token, std::size_t max_len = 24);

}  // namespace inhap
