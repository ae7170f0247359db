// Device bridge round trip over loopback: the C client sends a state, inhap's BridgeDevice
// (on its own thread, as in `inhap serve`) answers with a force; the time from the client's
// send to the force received, p50/p99 in microseconds. Unsigned and with an HMAC key.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "inhap/haptics/bridge_device.hpp"
#include "inhap_bridge.h"

namespace {

double percentile(std::vector<double>& v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

void BM_BridgeRoundTrip(benchmark::State& state, const char* key) {
  inhap::haptics::BridgeOptions o;
  o.port = 0;
  o.key = key;
  o.timeout_s = 0.5;
  inhap::haptics::BridgeDevice dev(o);
  std::atomic<bool> done{false};
  std::thread server([&] {
    if (!dev.connect(10.0)) return;
    while (!done.load(std::memory_order_relaxed)) {
      const inhap::Vec3 p = dev.position();
      dev.command_force({0.0, 0.0, p.z() < 0 ? -0.5 * p.z() : 0.0});
      dev.tick();
    }
  });
  inhap_bridge c;
  inhap_bridge_open(&c, "127.0.0.1", dev.port(), key);
  std::vector<double> us;
  us.reserve(1 << 20);
  double f[3];
  long i = 0;
  for (auto _ : state) {
    const double p[3] = {0.0, 0.0, 1.0 - 0.001 * static_cast<double>(i % 2000)};
    const auto t0 = std::chrono::steady_clock::now();
    const int r =
        inhap_bridge_exchange(&c, 1e-3 * static_cast<double>(i), p, nullptr, 0, f, nullptr, 100000);
    const auto t1 = std::chrono::steady_clock::now();
    if (r != 1) state.SkipWithError("no answer");
    us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    ++i;
  }
  done = true;
  // Wake the server's wait with one last state, then let it time out.
  const double p[3] = {0, 0, 0};
  inhap_bridge_exchange(&c, 0, p, nullptr, 0, f, nullptr, 1000);
  server.join();
  inhap_bridge_close(&c);
  if (!us.empty()) {
    state.counters["p50_us"] = percentile(us, 0.50);
    state.counters["p99_us"] = percentile(us, 0.99);
    state.counters["max_us"] = us.back();
  }
}

BENCHMARK_CAPTURE(BM_BridgeRoundTrip, unsigned, "")->Iterations(20000)->UseRealTime();
BENCHMARK_CAPTURE(BM_BridgeRoundTrip, hmac_sha256, "bench key")->Iterations(20000)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
