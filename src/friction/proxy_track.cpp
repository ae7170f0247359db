// The proxy estimator over a whole recording (see proxy_track.hpp).
#include "inhap/friction/proxy_track.hpp"

namespace inhap::friction {

ProxyColumns proxy_track(const ProxyModel& model, const Recording& rec) {
  const std::size_t n = rec.size();
  ProxyColumns c;
  c.q.resize(n);
  c.n.resize(n);
  c.contact.resize(n);
  c.sliding.resize(n);
  ProxyState state;
  for (std::size_t i = 0; i < n; ++i) {
    const double dt = i ? rec.t[i] - rec.t[i - 1] : 0.0;
    const ProxyOutput o = proxy_step(model, state, rec.p[i], dt);
    c.q[i] = o.q;
    c.n[i] = o.n;
    c.contact[i] = o.contact;
    c.sliding[i] = o.sliding;
    c.contact_count += o.contact;
    c.sliding_count += o.sliding;
  }
  return c;
}

}  // namespace inhap::friction
