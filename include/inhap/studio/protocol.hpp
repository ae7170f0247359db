// inhap studio: the WebSocket messages between the page and the server (docs/studio.md,
// "Protocol"). Every message is one JSON object with a string "type". A message that is not
// JSON, not an object, has an unknown type or a field of the wrong kind or range is refused
// with {"type":"error","request":TYPE,"message":...} and changes nothing: handlers read every
// field through these checked getters before they touch any state.
// Units: mm, N, s.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "inhap/core/error.hpp"

namespace inhap::studio {

/// A refused message (the reply's "message").
class ProtocolError : public Error {
 public:
  using Error::Error;
};

/// The message types the server accepts.
const std::vector<std::string>& message_types();

struct Message {
  std::string type;
  nlohmann::json body;  ///< the whole object
};

/// Limits checked on the raw text before it is parsed: a frame's size in bytes and how deeply
/// its arrays and objects nest (every message of the protocol nests at most 3 deep).
inline constexpr std::size_t kMaxMessageBytes = 1u << 20;
inline constexpr std::size_t kMaxMessageDepth = 32;

/// Input quoted in an error text or a log line: valid UTF-8 (a byte that does not start or
/// continue a valid sequence becomes U+FFFD), cut at a character boundary to at most max_bytes
/// (then "..." follows).
std::string quote_input(std::string_view s, std::size_t max_bytes = 64);
/// How deeply the arrays and objects of a JSON text nest (brackets outside strings), counted
/// without parsing; the count stops once it exceeds `limit`.
std::size_t json_depth(std::string_view text, std::size_t limit);
/// j.dump() that replaces invalid UTF-8 instead of throwing.
std::string dump_safe(const nlohmann::json& j);

/// Parses one text frame (at most kMaxMessageBytes, nested at most kMaxMessageDepth). Throws
/// ProtocolError: too large or deep, not JSON, not an object, no string "type", or a type not in
/// message_types().
Message parse_message(std::string_view text);

/// Checked getters: throw ProtocolError naming the field and what was expected.
double get_number(const Message& m, const char* key, double lo, double hi);
double get_number_or(const Message& m, const char* key, double lo, double hi, double fallback);
long get_integer(const Message& m, const char* key, long lo, long hi);
bool get_bool_or(const Message& m, const char* key, bool fallback);
std::string get_string(const Message& m, const char* key, std::size_t max_size = 1024);
/// One of `choices`.
std::string get_choice(const Message& m, const char* key, const std::vector<std::string>& choices);
/// A list of integers, each in [lo, hi], at most max_items.
std::vector<long> get_integer_list(const Message& m, const char* key, long lo, long hi,
                                   std::size_t max_items);

/// {"type":"error","request":request,"message":message}, both quoted with quote_input (64 and
/// 1024 bytes). Never throws.
std::string error_reply(std::string_view request, std::string_view message);

}  // namespace inhap::studio
