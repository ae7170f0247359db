// inhap studio: the HTTP + WebSocket server (civetweb, Debian libcivetweb-dev; docs/studio.md
// says why). Binds 127.0.0.1 only; every request and WebSocket upgrade is checked by
// security.hpp (token, Host, Origin); serves the page (web/studio/) and the JavaScript libraries
// from web/node_modules (three.js, plotly.js; offline, no CDN); hands WebSocket text frames to
// the Session and broadcasts the Session's stream to every open page.
// civetweb's worker threads only hand work over: HTTP requests and WebSocket upgrades run on the
// server's HTTP thread, WebSocket messages on its command worker (both threads of our own, with
// normal stacks). civetweb's own workers ask for 100 KB, of which glibc takes the static TLS;
// thread_stack.hpp gives them room for it.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

#include "inhap/studio/connection_limits.hpp"

struct mg_context;
struct mg_connection;

namespace inhap::studio {

/// The folder with studio/index.html and node_modules: `given`, else INHAP_WEB_DIR, else web/
/// beside or above the executable, else ./web. Throws Error naming what is missing.
std::string find_studio_web_dir(const std::string& given);

class Server {
 public:
  using Handler = std::function<std::string(const std::string&)>;
  /// Starts listening on 127.0.0.1:port (0: a free port). Throws Error when it cannot.
  Server(int port, std::string web_dir, std::string token);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  int port() const { return port_; }
  const std::string& token() const { return token_; }
  std::string url() const;
  /// Where WebSocket text frames go (set before the page connects; until then they are refused).
  void set_handler(Handler h);
  /// Queues a text frame for every open page. Each page has its own queue and writer thread: a
  /// page that stops reading never holds up the others. A full queue (kSendQueue) drops its
  /// oldest state message (else its oldest message) and counts it; the page is told the count
  /// ({"type":"dropped","count":N}) with its next message.
  void broadcast(const std::string& text);
  static constexpr std::size_t kSendQueue = 256;  ///< messages waiting for one page
  /// Messages of one page (and of all pages) waiting for the command worker; past it, a message
  /// is answered with a "busy" error and not run.
  static constexpr std::size_t kPageBacklog = 1024, kBacklog = 4096;
  /// Messages refused as busy so far (all pages).
  std::uint64_t busy_replies() const;
  std::size_t clients() const;
  /// civetweb's worker threads: every open page and every connection being read holds one.
  static constexpr int kWorkers = 128;
  /// Connections per client address (connection_limits.hpp), kept below kWorkers.
  const ConnectionLimits& connection_limits() const { return limits_; }
  /// Stops running messages (waits for the one running); later messages are dropped. Call before
  /// the handler's target goes away.
  void stop_handling();

  // civetweb callbacks (public for the C trampolines): on civetweb's worker threads
  int on_http(mg_connection* conn);
  int on_ws_connect(const mg_connection* conn);
  void on_ws_ready(mg_connection* conn);
  int on_ws_data(mg_connection* conn, int bits, char* data, std::size_t len);
  void on_ws_close(const mg_connection* conn);
  void on_connection_open(const mg_connection* conn);
  void on_request(const mg_connection* conn);
  void on_connection_close(const mg_connection* conn);

 private:
  bool allowed(const mg_connection* conn, bool websocket) const;
  int serve_http(mg_connection* conn);  // on the HTTP thread
  int hand_over(mg_connection* conn, bool websocket);
  void http_work();
  void stop_http();
  void work();
  void send_to(const mg_connection* conn, const std::string& text);
  // One open page: its send queue and writer thread (all fields under mu_).
  struct Client {
    mg_connection* conn = nullptr;
    std::deque<std::string> out;
    std::uint64_t dropped = 0, dropped_told = 0;
    std::size_t backlog = 0;  ///< its messages waiting for the command worker
    bool closing = false;
    std::condition_variable cv;
    std::thread writer;
  };
  void enqueue(Client& c, const std::string& text);  // under mu_
  void write_loop(Client* c);
  void close_clients();  // before mg_stop: ends every writer
  std::string web_dir_, token_;
  int port_ = 0;
  mg_context* ctx_ = nullptr;
  std::atomic<int> listen_port_{0};  ///< port_ for civetweb's threads
  // civetweb fills a connection's client address (request_info's remote_addr and remote_port)
  // before init_connection, but mg_get_request_info() returns null until the request has
  // arrived. The offset of request_info in the connection is learnt from the first request
  // (the server sends one to itself when it starts) and used for the connections after it.
  std::atomic<std::ptrdiff_t> request_info_offset_{-1};
  void learn_request_info_offset();
  ConnectionLimits limits_;
  // Trims limits_ every 50 ms (with every worker held, no connection opens to do it).
  void trim_loop();
  std::mutex trim_mu_;
  std::condition_variable trim_cv_;
  bool trim_quit_ = false;
  std::thread trim_thread_;
  mutable std::mutex mu_;
  std::map<const mg_connection*, std::unique_ptr<Client>> clients_;
  bool closing_all_ = false;
  std::uint64_t busy_ = 0;
  Handler handler_;
  // Messages run on one worker thread of our own (civetweb's threads have small stacks, too
  // small for the reconstruction), in arrival order; the reply goes to the sender if it is
  // still connected.
  std::deque<std::pair<mg_connection*, std::string>> queue_;
  std::condition_variable queue_cv_;
  bool quit_ = false;
  std::thread worker_;
  // HTTP requests and WebSocket upgrades: civetweb's thread waits while the HTTP thread checks
  // the request and writes the reply (a page load is not held up by a reconstruction).
  struct HttpJob {
    mg_connection* conn = nullptr;
    bool websocket = false;
    int result = 0;
    bool done = false;
  };
  std::mutex http_mu_;
  std::condition_variable http_cv_, http_done_cv_;
  std::deque<HttpJob*> http_jobs_;
  bool http_quit_ = false;
  std::thread http_thread_;
};

/// The server on `port`, or, when `next_if_busy` and that port is taken, on the first free one of
/// the `tries` ports after it (port 0: any free port). Throws Error naming the ports tried.
std::unique_ptr<Server> listen_on(int port, bool next_if_busy, const std::string& web_dir,
                                  const std::string& token, int tries = 20);

}  // namespace inhap::studio
