/* inhap device bridge client: C99, one .c and one .h, no dependencies (POSIX sockets or
 * Winsock 2). Put it beside a vendor SDK (OpenHaptics, Force Dimension, CHAI3D, ...) and call
 * inhap_bridge_exchange() once per servo tick from the device callback: it sends the probe
 * position (and the raw force-sensor reading, if there is one) to inhap and returns the force
 * to command. Protocol: docs/bridge.md. Units: mm, N, s.
 *
 *   inhap_bridge b;
 *   if (inhap_bridge_open(&b, "127.0.0.1", 47110, NULL) != 0) { ... }   // key: NULL on loopback
 *   // in the 1 kHz callback:
 *   double f[3]; unsigned status;
 *   inhap_bridge_exchange(&b, t_s, p_mm, sensor_n_or_NULL, buttons, f, &status, 2000);
 *   // command f (N); it is zero when inhap did not answer within the time-out
 *   inhap_bridge_close(&b);
 */
#ifndef INHAP_BRIDGE_H
#define INHAP_BRIDGE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define INHAP_BRIDGE_MAGIC 0x42504849u
#define INHAP_BRIDGE_VERSION 1
#define INHAP_BRIDGE_DEFAULT_PORT 47110
#define INHAP_BRIDGE_STATUS_CONTACT 1u
#define INHAP_BRIDGE_STATUS_ZEROED 2u
#define INHAP_BRIDGE_STATUS_STOPPING 4u

typedef struct inhap_bridge_stats {
  uint64_t sent;       /* state packets sent */
  uint64_t answered;   /* exchanges answered in time */
  uint64_t timeouts;   /* exchanges with no answer in time (force zero) */
  uint64_t stale;      /* answers to an older sequence, dropped */
  uint64_t malformed;  /* datagrams that are not a valid force packet */
  uint64_t bad_auth;   /* unsigned or wrong tag while a key is set */
} inhap_bridge_stats;

typedef struct inhap_bridge {
  intptr_t sock;                /* socket handle (int on POSIX, SOCKET on Windows) */
  unsigned char addr[16];       /* the inhap side (struct sockaddr_in) */
  uint32_t session;
  uint32_t sequence;
  int has_key;
  unsigned char key[64];        /* HMAC key block of the shared secret */
  int has_session_key;          /* with a key: the handshake of this session is done */
  unsigned char session_key[64]; /* HMAC key block of this session (from the handshake) */
  unsigned char nonce[32];      /* this side's nonce of the last hello */
  unsigned long misses;         /* time-outs in a row (with a key, 100 start a new handshake) */
  inhap_bridge_stats stats;
  long spin_us;                 /* busy-wait this long for the force before sleeping (default
                                   INHAP_BRIDGE_SPIN_US; 0: always sleep) */
} inhap_bridge;

/* The answer usually comes within tens of microseconds; waiting for it without sleeping saves
 * the wake-up of a sleeping thread (several microseconds, more in a virtual machine). */
#define INHAP_BRIDGE_SPIN_US 200L

/* Opens a UDP socket towards inhap at host (IPv4 dotted quad) and port. key: shared secret
 * (any length) for HMAC-SHA256, or NULL/"" for none (loopback). Returns 0, or -1 on error. */
int inhap_bridge_open(inhap_bridge* b, const char* host, unsigned short port, const char* key);

/* One servo tick: sends the state (time s, position mm, sensor force N or NULL, buttons) and
 * waits up to timeout_us for inhap's force (N) for this tick, the first b->spin_us of it without
 * sleeping. With a key, the first exchange (and one after 100 time-outs in a row) first makes
 * the handshake that gives the session its key (hello, welcome: up to timeout_us; no state is
 * sent when it times out). Returns 1 with force_out set, 0 on time-out (force_out zero), -1 on a socket error
 * (force_out zero). status_out may be NULL. */
int inhap_bridge_exchange(inhap_bridge* b, double time_s, const double position_mm[3],
                          const double* sensor_force_n, uint32_t buttons, double force_out[3],
                          uint32_t* status_out, long timeout_us);

void inhap_bridge_close(inhap_bridge* b);

/* HMAC-SHA256 (exposed for tests): tag = HMAC(key block, data). */
void inhap_bridge_hmac_sha256(const unsigned char key[64], const unsigned char* data, size_t n,
                              unsigned char tag[32]);

#ifdef __cplusplus
}
#endif

#endif /* INHAP_BRIDGE_H */
