/* inhap device bridge client, C99. See inhap_bridge.h and docs/bridge.md. */
#if !defined(_WIN32) && !defined(_POSIX_C_SOURCE)
#define _POSIX_C_SOURCE 200809L
#endif
#ifdef _WIN32
#define _CRT_RAND_S /* rand_s: the system's cryptographic generator */
#endif
#include "inhap_bridge.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#ifdef _WIN32
#include <winsock2.h>
#include <ws2tcpip.h>
typedef int socklen_t;
#define INHAP_CLOSE closesocket
#else
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>
#define INHAP_CLOSE close
#endif

#define STATE_BODY 76
#define FORCE_BODY 44
#define TAG 32
#define NONCE 32
#define HELLO_BODY (16 + NONCE)
#define WELCOME_BODY (16 + 2 * NONCE)
#define REHANDSHAKE_AFTER 100 /* time-outs in a row (with a key): the session key is stale */
#define FLAG_SENSOR 1u
#define FLAG_SIGNED 2u

/* ---- SHA-256 (FIPS 180-4) and HMAC (RFC 2104) ------------------------------------------ */

static const uint32_t K256[64] = {
    0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4, 0xab1c5ed5,
    0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe, 0x9bdc06a7, 0xc19bf174,
    0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f, 0x4a7484aa, 0x5cb0a9dc, 0x76f988da,
    0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7, 0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967,
    0x27b70a85, 0x2e1b2138, 0x4d2c6dfc, 0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85,
    0xa2bfe8a1, 0xa81a664b, 0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070,
    0x19a4c116, 0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
    0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7, 0xc67178f2};

typedef struct {
  uint32_t h[8];
  unsigned char block[64];
  size_t used;
  uint64_t bytes;
} sha256_ctx;

static uint32_t rotr(uint32_t x, int n) { return (x >> n) | (x << (32 - n)); }

static void sha256_compress(sha256_ctx* c, const unsigned char* p) {
  uint32_t w[64], a, b, cc, d, e, f, g, h;
  int i;
  for (i = 0; i < 16; ++i)
    w[i] = ((uint32_t)p[4 * i] << 24) | ((uint32_t)p[4 * i + 1] << 16) |
           ((uint32_t)p[4 * i + 2] << 8) | (uint32_t)p[4 * i + 3];
  for (i = 16; i < 64; ++i) {
    uint32_t s0 = rotr(w[i - 15], 7) ^ rotr(w[i - 15], 18) ^ (w[i - 15] >> 3);
    uint32_t s1 = rotr(w[i - 2], 17) ^ rotr(w[i - 2], 19) ^ (w[i - 2] >> 10);
    w[i] = w[i - 16] + s0 + w[i - 7] + s1;
  }
  a = c->h[0]; b = c->h[1]; cc = c->h[2]; d = c->h[3];
  e = c->h[4]; f = c->h[5]; g = c->h[6]; h = c->h[7];
  for (i = 0; i < 64; ++i) {
    uint32_t t1 = h + (rotr(e, 6) ^ rotr(e, 11) ^ rotr(e, 25)) + ((e & f) ^ (~e & g)) + K256[i] + w[i];
    uint32_t t2 = (rotr(a, 2) ^ rotr(a, 13) ^ rotr(a, 22)) + ((a & b) ^ (a & cc) ^ (b & cc));
    h = g; g = f; f = e; e = d + t1; d = cc; cc = b; b = a; a = t1 + t2;
  }
  c->h[0] += a; c->h[1] += b; c->h[2] += cc; c->h[3] += d;
  c->h[4] += e; c->h[5] += f; c->h[6] += g; c->h[7] += h;
}

static void sha256_init(sha256_ctx* c) {
  static const uint32_t iv[8] = {0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a,
                                 0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19};
  memcpy(c->h, iv, sizeof iv);
  c->used = 0;
  c->bytes = 0;
}

static void sha256_update(sha256_ctx* c, const unsigned char* p, size_t n) {
  c->bytes += n;
  while (n > 0) {
    size_t take = 64 - c->used;
    if (take > n) take = n;
    memcpy(c->block + c->used, p, take);
    c->used += take;
    p += take;
    n -= take;
    if (c->used == 64) {
      sha256_compress(c, c->block);
      c->used = 0;
    }
  }
}

static void sha256_final(sha256_ctx* c, unsigned char out[32]) {
  uint64_t bits = c->bytes * 8;
  unsigned char pad = 0x80, zero = 0, len[8];
  int i;
  sha256_update(c, &pad, 1);
  while (c->used != 56) sha256_update(c, &zero, 1);
  for (i = 0; i < 8; ++i) len[i] = (unsigned char)(bits >> (56 - 8 * i));
  sha256_update(c, len, 8);
  for (i = 0; i < 8; ++i) {
    out[4 * i] = (unsigned char)(c->h[i] >> 24);
    out[4 * i + 1] = (unsigned char)(c->h[i] >> 16);
    out[4 * i + 2] = (unsigned char)(c->h[i] >> 8);
    out[4 * i + 3] = (unsigned char)c->h[i];
  }
}

void inhap_bridge_hmac_sha256(const unsigned char key[64], const unsigned char* data, size_t n,
                              unsigned char tag[32]) {
  unsigned char pad[64], inner[32];
  sha256_ctx c;
  int i;
  for (i = 0; i < 64; ++i) pad[i] = (unsigned char)(key[i] ^ 0x36);
  sha256_init(&c);
  sha256_update(&c, pad, 64);
  sha256_update(&c, data, n);
  sha256_final(&c, inner);
  for (i = 0; i < 64; ++i) pad[i] = (unsigned char)(key[i] ^ 0x5c);
  sha256_init(&c);
  sha256_update(&c, pad, 64);
  sha256_update(&c, inner, 32);
  sha256_final(&c, tag);
}

/* ---- little-endian encoding ------------------------------------------------------------- */

static void put_u16(unsigned char* o, uint16_t v) {
  o[0] = (unsigned char)v;
  o[1] = (unsigned char)(v >> 8);
}
static void put_u32(unsigned char* o, uint32_t v) {
  int i;
  for (i = 0; i < 4; ++i) o[i] = (unsigned char)(v >> (8 * i));
}
static void put_f64(unsigned char* o, double v) {
  uint64_t u;
  int i;
  if (!(v == v) || v > 1.7976931348623157e308 || v < -1.7976931348623157e308) v = 0.0;
  memcpy(&u, &v, 8);
  for (i = 0; i < 8; ++i) o[i] = (unsigned char)(u >> (8 * i));
}
static uint32_t get_u32(const unsigned char* b) {
  return (uint32_t)b[0] | ((uint32_t)b[1] << 8) | ((uint32_t)b[2] << 16) | ((uint32_t)b[3] << 24);
}
static double get_f64(const unsigned char* b) {
  uint64_t u = 0;
  double v;
  int i;
  for (i = 0; i < 8; ++i) u |= (uint64_t)b[i] << (8 * i);
  memcpy(&v, &u, 8);
  return v;
}

static int tags_equal(const unsigned char* a, const unsigned char* b) {
  unsigned char d = 0;
  int i;
  for (i = 0; i < TAG; ++i) d |= (unsigned char)(a[i] ^ b[i]);
  return d == 0;
}

/* n random bytes from the system's generator; 0, or -1 when there is none. */
static int random_bytes(unsigned char* out, size_t n) {
#ifdef _WIN32
  size_t i;
  for (i = 0; i < n; ++i) {
    unsigned int r;
    if (rand_s(&r) != 0) return -1;
    out[i] = (unsigned char)r;
  }
  return 0;
#else
  size_t got;
  FILE* f = fopen("/dev/urandom", "rb");
  if (!f) return -1;
  got = fread(out, 1, n, f);
  fclose(f);
  return got == n ? 0 : -1;
#endif
}

static void put_header(unsigned char* d, unsigned kind, unsigned flags, uint32_t session,
                       uint32_t sequence) {
  put_u32(d, INHAP_BRIDGE_MAGIC);
  put_u16(d + 4, INHAP_BRIDGE_VERSION);
  d[6] = (unsigned char)kind;
  d[7] = (unsigned char)flags;
  put_u32(d + 8, session);
  put_u32(d + 12, sequence);
}

/* The welcome to our hello: 1 with the session key derived, 0 to be ignored (counted). */
static int read_welcome(inhap_bridge* b, const unsigned char* d, long n) {
  static const char label[] = "inhap bridge session key v1";
  unsigned char in[sizeof label - 1 + 4 + 2 * NONCE], tag[TAG];
  if (n != WELCOME_BODY + TAG || get_u32(d) != INHAP_BRIDGE_MAGIC ||
      d[4] != INHAP_BRIDGE_VERSION || d[5] != 0 || d[6] != 4 || !(d[7] & FLAG_SIGNED)) {
    b->stats.malformed++;
    return 0;
  }
  inhap_bridge_hmac_sha256(b->key, d, WELCOME_BODY, tag);
  if (!tags_equal(tag, d + WELCOME_BODY)) {
    b->stats.bad_auth++;
    return 0;
  }
  if (get_u32(d + 8) != b->session || memcmp(d + 16, b->nonce, NONCE) != 0) {
    b->stats.stale++;
    return 0;
  }
  /* key = HMAC(shared, label | session | client nonce | server nonce), as inhap derives it */
  memcpy(in, label, sizeof label - 1);
  put_u32(in + sizeof label - 1, b->session);
  memcpy(in + sizeof label - 1 + 4, d + 16, 2 * NONCE);
  memset(b->session_key, 0, sizeof b->session_key);
  inhap_bridge_hmac_sha256(b->key, in, sizeof in, b->session_key);
  b->has_session_key = 1;
  b->misses = 0;
  return 1;
}

/* ---- client ----------------------------------------------------------------------------- */

static uint32_t new_session(void) {
  /* A session id that differs between runs of the device process (no crypto needed: the key,
   * not the session id, is what authenticates). */
  uint32_t s = (uint32_t)time(NULL) * 2654435761u;
  s ^= (uint32_t)clock() * 40503u;
  s ^= (uint32_t)(uintptr_t)&s;
  return s ? s : 1u;
}

int inhap_bridge_open(inhap_bridge* b, const char* host, unsigned short port, const char* key) {
  struct sockaddr_in sa;
  memset(b, 0, sizeof *b);
#ifdef _WIN32
  {
    WSADATA w;
    if (WSAStartup(MAKEWORD(2, 2), &w) != 0) return -1;
  }
#endif
  memset(&sa, 0, sizeof sa);
  sa.sin_family = AF_INET;
  sa.sin_port = htons(port);
  if (inet_pton(AF_INET, host, &sa.sin_addr) != 1) return -1;
  memcpy(b->addr, &sa, sizeof sa);
  b->sock = (intptr_t)socket(AF_INET, SOCK_DGRAM, 0);
  if (b->sock < 0) return -1;
  if (key && key[0]) {
    size_t n = strlen(key);
    b->has_key = 1;
    if (n > 64) {
      sha256_ctx c;
      sha256_init(&c);
      sha256_update(&c, (const unsigned char*)key, n);
      sha256_final(&c, b->key);
    } else {
      memcpy(b->key, key, n);
    }
  }
  b->session = new_session();
  b->sequence = 0;
  b->spin_us = INHAP_BRIDGE_SPIN_US;
  return 0;
}

void inhap_bridge_close(inhap_bridge* b) {
  if (b->sock >= 0) INHAP_CLOSE((int)b->sock);
  b->sock = -1;
#ifdef _WIN32
  WSACleanup();
#endif
}

/* Waits until the socket is readable or timeout_us passed; 1 readable, 0 time-out. */
static int wait_readable(intptr_t sock, long timeout_us) {
#ifdef _WIN32
  fd_set set;
  struct timeval tv;
  FD_ZERO(&set);
  FD_SET((SOCKET)sock, &set);
  tv.tv_sec = timeout_us / 1000000;
  tv.tv_usec = timeout_us % 1000000;
  return select(0, &set, NULL, NULL, &tv) > 0;
#else
  struct pollfd p;
  p.fd = (int)sock;
  p.events = POLLIN;
  p.revents = 0;
  return poll(&p, 1, (int)((timeout_us + 999) / 1000)) > 0;
#endif
}

/* Microseconds from a monotonic clock. */
static double now_us(void) {
#ifdef _WIN32
  LARGE_INTEGER f, c;
  QueryPerformanceFrequency(&f);
  QueryPerformanceCounter(&c);
  return (double)c.QuadPart * 1e6 / (double)f.QuadPart;
#else
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec * 1e6 + (double)t.tv_nsec * 1e-3;
#endif
}

/* Returns 1 if the datagram is the force answer to b->sequence (force/status set), 0 if it is
 * to be ignored (counted). */
static int read_answer(inhap_bridge* b, const unsigned char* d, long n, double f[3],
                       uint32_t* status) {
  int signed_ = n >= 8 && (d[7] & FLAG_SIGNED);
  long want = FORCE_BODY + (signed_ ? TAG : 0);
  int i;
  if (n != want || get_u32(d) != INHAP_BRIDGE_MAGIC || d[4] != INHAP_BRIDGE_VERSION || d[5] != 0 ||
      d[6] != 2) {
    b->stats.malformed++;
    return 0;
  }
  if (b->has_key) {
    unsigned char tag[TAG];
    if (!signed_) {
      b->stats.bad_auth++;
      return 0;
    }
    inhap_bridge_hmac_sha256(b->session_key, d, FORCE_BODY, tag);
    if (!tags_equal(tag, d + FORCE_BODY)) {
      b->stats.bad_auth++;
      return 0;
    }
  }
  if (get_u32(d + 8) != b->session || get_u32(d + 12) != b->sequence) {
    b->stats.stale++;
    return 0;
  }
  for (i = 0; i < 3; ++i) {
    f[i] = get_f64(d + 16 + 8 * i);
    if (!(f[i] == f[i]) || f[i] > 1e6 || f[i] < -1e6) {
      b->stats.malformed++;
      return 0;
    }
  }
  *status = get_u32(d + 40);
  return 1;
}

/* With a key: hello (a fresh nonce) and wait up to timeout_us for inhap's welcome. 1 with the
 * session key, 0 on time-out, -1 on a socket error or no random source. */
static int handshake(inhap_bridge* b, long timeout_us) {
  unsigned char d[WELCOME_BODY + TAG + 64];
  double t0;
  if (random_bytes(b->nonce, NONCE) != 0) return -1;
  put_header(d, 3, FLAG_SIGNED, b->session, 0);
  memcpy(d + 16, b->nonce, NONCE);
  inhap_bridge_hmac_sha256(b->key, d, HELLO_BODY, d + HELLO_BODY);
  if (sendto((int)b->sock, (const char*)d, (int)(HELLO_BODY + TAG), 0,
             (const struct sockaddr*)b->addr, sizeof(struct sockaddr_in)) != (long)(HELLO_BODY + TAG))
    return -1;
  t0 = now_us();
  for (;;) {
    long got, left = timeout_us - (long)(now_us() - t0);
    if (left <= 0 || !wait_readable(b->sock, left)) return 0;
    got = (long)recv((int)b->sock, (char*)d, sizeof d, 0);
    if (got < 0) return -1;
    if (read_welcome(b, d, got)) return 1;
  }
}

/* Polls without sleeping for up to spin_us; 1 as soon as the socket is readable. */
static int spin_readable(intptr_t sock, long spin_us) {
  const double t0 = now_us();
  do {
    if (wait_readable(sock, 0)) return 1;
  } while (now_us() - t0 < (double)spin_us);
  return 0;
}

int inhap_bridge_exchange(inhap_bridge* b, double time_s, const double position_mm[3],
                          const double* sensor_force_n, uint32_t buttons, double force_out[3],
                          uint32_t* status_out, long timeout_us) {
  unsigned char d[STATE_BODY + TAG + 64];
  double t0;
  uint32_t status = 0;
  int i;
  size_t n = STATE_BODY;
  force_out[0] = force_out[1] = force_out[2] = 0.0;
  if (status_out) *status_out = 0;
  if (b->has_key && b->misses >= REHANDSHAKE_AFTER) b->has_session_key = 0;
  if (b->has_key && !b->has_session_key) { /* a session starts with a handshake */
    const int h = handshake(b, timeout_us);
    if (h < 0) return -1;
    if (h == 0) {
      b->stats.timeouts++;
      return 0;
    }
  }
  b->sequence++;
  put_header(d, 1, (sensor_force_n ? FLAG_SENSOR : 0u) | (b->has_key ? FLAG_SIGNED : 0u),
             b->session, b->sequence);
  put_f64(d + 16, time_s);
  for (i = 0; i < 3; ++i) put_f64(d + 24 + 8 * i, position_mm[i]);
  for (i = 0; i < 3; ++i) put_f64(d + 48 + 8 * i, sensor_force_n ? sensor_force_n[i] : 0.0);
  put_u32(d + 72, buttons);
  if (b->has_key) {
    inhap_bridge_hmac_sha256(b->session_key, d, STATE_BODY, d + STATE_BODY);
    n += TAG;
  }
  if (sendto((int)b->sock, (const char*)d, (int)n, 0, (const struct sockaddr*)b->addr,
             sizeof(struct sockaddr_in)) != (long)n)
    return -1;
  b->stats.sent++;
  t0 = now_us();
  for (;;) {
    long left = timeout_us - (long)(now_us() - t0);
    long got;
    double f[3];
    if (left <= 0) {
      b->stats.timeouts++;
      b->misses++;
      return 0;
    }
    if (!spin_readable(b->sock, left < b->spin_us ? left : b->spin_us)) {
      left = timeout_us - (long)(now_us() - t0);
      if (left <= 0 || !wait_readable(b->sock, left)) {
        b->stats.timeouts++;
        b->misses++;
        return 0;
      }
    }
    got = (long)recv((int)b->sock, (char*)d, sizeof d, 0);
    if (got < 0) return -1;
    if (read_answer(b, d, got, f, &status)) {
      force_out[0] = f[0];
      force_out[1] = f[1];
      force_out[2] = f[2];
      if (status_out) *status_out = status;
      b->stats.answered++;
      b->misses = 0;
      return 1;
    }
  }
}
