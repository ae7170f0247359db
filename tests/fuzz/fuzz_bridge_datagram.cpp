// The bridge's datagram parser, as BridgeDevice and a client run it on every datagram: every
// packet kind decoded with no key, with a shared key and with a session key. Anything decoded
// must be finite and within the plausibility limits; a crash, an exception or a sanitizer report
// is a finding.
#include <cmath>
#include <cstdlib>

#include "fuzz_common.hpp"
#include "inhap/haptics/bridge_protocol.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace inhap::haptics;
  static const BridgeKey none, shared("fuzz key"), session = session_key(shared, 7, {}, {});
  const std::span<const std::uint8_t> b(data, size);
  (void)packet_kind(b);
  for (const BridgeKey* k : {&none, &shared, &session}) {
    StatePacket s;
    if (decode(b, *k, s) == DecodeResult::kOk &&
        (!std::isfinite(s.device_time_s) || std::abs(s.device_time_s) > kMaxDeviceTimeS ||
         !s.position_mm.allFinite() || s.position_mm.cwiseAbs().maxCoeff() > kMaxPositionMm ||
         !s.sensor_force_n.allFinite()))
      std::abort();
    ForcePacket f;
    if (decode(b, *k, f) == DecodeResult::kOk && !f.force_n.allFinite()) std::abort();
    HelloPacket h;
    (void)decode(b, *k, h);
    WelcomePacket w;
    (void)decode(b, *k, w);
  }
  return 0;
}
