#include "inhap/studio/server.hpp"

#include <arpa/inet.h>
#include <civetweb.h>
#include <fmt/format.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "inhap/core/error.hpp"
#include "inhap/core/web_dir.hpp"
#include "inhap/studio/protocol.hpp"
#include "inhap/studio/security.hpp"
#include "inhap/studio/thread_stack.hpp"

namespace fs = std::filesystem;

namespace inhap::studio {
namespace {

// URL path -> file below the web folder. The page's own files are listed, nothing else is served.
const std::map<std::string, std::pair<std::string, std::string>>& routes() {
  static const std::map<std::string, std::pair<std::string, std::string>> r = {
      {"/", {"studio/index.html", "text/html; charset=utf-8"}},
      {"/index.html", {"studio/index.html", "text/html; charset=utf-8"}},
      {"/studio.js", {"studio/studio.js", "text/javascript; charset=utf-8"}},
      {"/studio.css", {"studio/studio.css", "text/css; charset=utf-8"}},
      {"/plots.js", {"studio/plots.js", "text/javascript; charset=utf-8"}},
      {"/markers.js", {"studio/markers.js", "text/javascript; charset=utf-8"}},
      {"/model.js", {"studio/model.js", "text/javascript; charset=utf-8"}},
      {"/lib/three.module.js", {"node_modules/three/build/three.module.js", "text/javascript"}},
      {"/lib/three.core.js", {"node_modules/three/build/three.core.js", "text/javascript"}},
      {"/lib/OrbitControls.js",
       {"node_modules/three/examples/jsm/controls/OrbitControls.js", "text/javascript"}},
      {"/lib/plotly.min.js", {"node_modules/plotly.js-dist-min/plotly.min.js", "text/javascript"}},
  };
  return r;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void send_text(mg_connection* conn, int status, const char* reason, const std::string& body,
               const char* type = "text/plain; charset=utf-8", const std::string& extra = {}) {
  // Built here and written with mg_write (mg_printf formats into an 8 KB stack buffer).
  const std::string head = fmt::format(
      "HTTP/1.1 {} {}\r\nContent-Type: {}\r\nContent-Length: {}\r\nCache-Control: "
      "no-store\r\nX-Content-Type-Options: nosniff\r\nX-Frame-Options: DENY\r\n"
      "Referrer-Policy: no-referrer\r\n{}Connection: close\r\n\r\n",
      status, reason, type, body.size(), extra);
  mg_write(conn, head.data(), head.size());
  mg_write(conn, body.data(), body.size());
}

const char* header(const mg_connection* conn, const char* name) {
  const char* h = mg_get_header(conn, name);
  return h ? h : "";
}

int http_cb(mg_connection* conn, void* self) {
  return static_cast<Server*>(self)->on_http(conn);
}
int ws_connect_cb(const mg_connection* conn, void* self) {
  return static_cast<Server*>(self)->on_ws_connect(conn);
}
void ws_ready_cb(mg_connection* conn, void* self) {
  static_cast<Server*>(self)->on_ws_ready(conn);
}
int ws_data_cb(mg_connection* conn, int bits, char* data, size_t len, void* self) {
  return static_cast<Server*>(self)->on_ws_data(conn, bits, data, len);
}
void ws_close_cb(const mg_connection* conn, void* self) {
  static_cast<Server*>(self)->on_ws_close(conn);
}
// The connection callbacks get the Server from the context's user data (mg_start's argument).
Server* server_of(const mg_connection* conn) {
  return static_cast<Server*>(mg_get_user_data(mg_get_context(conn)));
}
int init_connection_cb(const mg_connection* conn, void** conn_data) {
  *conn_data = nullptr;
  server_of(conn)->on_connection_open(conn);
  return 0;
}
int begin_request_cb(mg_connection* conn) {
  server_of(conn)->on_request(conn);
  return 0;  // civetweb goes on to the handlers
}
void connection_close_cb(const mg_connection* conn) {
  server_of(conn)->on_connection_close(conn);
}

bool has_studio(const fs::path& d) {
  return fs::exists(d / "studio/index.html");
}

}  // namespace

std::string find_studio_web_dir(const std::string& given) {
  const std::string dir = find_web_dir(given, has_studio, "the studio page web/studio/index.html");
  for (const auto& [url, file] : routes())
    if (!fs::exists(fs::path(dir) / file.first))
      throw Error(fmt::format("{}: {} is missing: run ./run setup (it runs npm ci --prefix web)",
                              dir, file.first));
  return dir;
}

Server::Server(int port, std::string web_dir, std::string token)
    : web_dir_(std::move(web_dir)),
      token_(std::move(token)),
      limits_([this](const std::string& address, int peer_port, bool refuse) {
        shutdown_peer_socket(address, peer_port, listen_port_.load(), refuse);
      }) {
  if (port < 0 || port > 65535) throw Error("--port: expected 0-65535");
  // civetweb's workers ask for 100 KB of stack; thread_stack.cpp (linked in by this call) gives
  // them room for the static TLS on top.
  if (stack_size_granted(102400) <= 102400) throw Error("studio: no room for civetweb's stacks");
  mg_init_library(0);
  const std::string ports = fmt::format("127.0.0.1:{}", port);
  // Every open page holds one of civetweb's workers, and so does a connection whose request
  // has not arrived yet: 2 s for a request (headers and body) and for each write to a page, so
  // slow or silent connections (no token needed to open one) free their worker soon and a page
  // that stops reading blocks only its own writer. civetweb has no per-client limit: the
  // connection callbacks below count connections per client address (ConnectionLimits), so
  // connections without a request cannot take more than kPendingTotal of the workers.
  const std::string workers = std::to_string(kWorkers);
  const char* options[] = {"listening_ports",
                           ports.c_str(),
                           "num_threads",
                           workers.c_str(),
                           "connection_queue",
                           "64",
                           "request_timeout_ms",
                           "2000",
                           "max_request_size",
                           "16384",
                           "enable_keep_alive",
                           "no",
                           "websocket_timeout_ms",
                           "3600000",
                           "tcp_nodelay",
                           "1",
                           nullptr};
  mg_callbacks callbacks{};
  callbacks.init_connection = init_connection_cb;
  callbacks.begin_request = begin_request_cb;
  callbacks.connection_close = connection_close_cb;
  ctx_ = mg_start(&callbacks, this, options);
  if (!ctx_) {
    mg_exit_library();
    throw Error(fmt::format("cannot listen on {} (in use?)", ports));
  }
  std::array<mg_server_port, 4> sp{};
  if (mg_get_server_ports(ctx_, int(sp.size()), sp.data()) < 1) {
    mg_stop(ctx_);
    throw Error("civetweb: no listening port");
  }
  port_ = sp[0].port;
  listen_port_ = port_;
  http_thread_ = std::thread([this] { http_work(); });
  trim_thread_ = std::thread([this] { trim_loop(); });
  worker_ = std::thread([this] { work(); });
  mg_set_request_handler(ctx_, "/", http_cb, this);
  mg_set_websocket_handler(ctx_, "/ws", ws_connect_cb, ws_ready_cb, ws_data_cb, ws_close_cb, this);
  learn_request_info_offset();
}

Server::~Server() {
  {
    std::lock_guard lock(trim_mu_);
    trim_quit_ = true;
  }
  trim_cv_.notify_all();
  if (trim_thread_.joinable()) trim_thread_.join();
  stop_handling();
  close_clients();          // the writers end before civetweb frees the connections
  if (ctx_) mg_stop(ctx_);  // waits for civetweb's threads, which may wait for the HTTP thread
  stop_http();
  mg_exit_library();
}

std::unique_ptr<Server> listen_on(int port, bool next_if_busy, const std::string& web_dir,
                                  const std::string& token, int tries) {
  if (port == 0 || !next_if_busy) return std::make_unique<Server>(port, web_dir, token);
  for (int p = port; p <= std::min(port + tries, 65535); ++p) {
    try {
      return std::make_unique<Server>(p, web_dir, token);
    } catch (const Error&) {  // in use: the next one
    }
  }
  throw Error(fmt::format("cannot listen on 127.0.0.1 ports {}-{} (all in use?); try --port 0",
                          port, std::min(port + tries, 65535)));
}

std::string Server::url() const {
  return fmt::format("http://127.0.0.1:{}/?token={}", port_, token_);
}

void Server::stop_handling() {
  {
    std::lock_guard lock(mu_);
    quit_ = true;
    handler_ = {};
  }
  queue_cv_.notify_all();
  if (worker_.joinable()) worker_.join();
}

void Server::set_handler(Handler h) {
  std::lock_guard lock(mu_);
  handler_ = std::move(h);
}

std::size_t Server::clients() const {
  std::lock_guard lock(mu_);
  return clients_.size();
}

std::uint64_t Server::busy_replies() const {
  std::lock_guard lock(mu_);
  return busy_;
}

bool Server::allowed(const mg_connection* conn, bool websocket) const {
  const mg_request_info* ri = mg_get_request_info(conn);
  if (!host_allowed(header(conn, "Host"), port_)) return false;
  if (!origin_allowed(header(conn, "Origin"), port_, websocket)) return false;
  return request_authorized(ri->query_string ? ri->query_string : "", header(conn, "Cookie"),
                            token_);
}

// civetweb's worker thread (stack 100 KB in Debian's build, fixed at build time) only queues
// the request and waits; the HTTP thread checks it and writes the reply on the connection.
int Server::hand_over(mg_connection* conn, bool websocket) {
  HttpJob job;
  job.conn = conn;
  job.websocket = websocket;
  std::unique_lock lock(http_mu_);
  http_jobs_.push_back(&job);
  http_cv_.notify_one();
  http_done_cv_.wait(lock, [&job] { return job.done; });
  return job.result;
}

void Server::http_work() {
  std::unique_lock lock(http_mu_);
  for (;;) {
    http_cv_.wait(lock, [this] { return http_quit_ || !http_jobs_.empty(); });
    if (http_jobs_.empty()) return;  // quitting, nothing left
    HttpJob* job = http_jobs_.front();
    http_jobs_.pop_front();
    lock.unlock();
    int result = 500;
    try {
      result = job->websocket ? (allowed(job->conn, true) ? 0 : 1) : serve_http(job->conn);
    } catch (const std::exception&) {  // e.g. out of memory: refuse this one, keep serving
      if (job->websocket) result = 1;
    }
    lock.lock();
    job->result = result;
    job->done = true;
    http_done_cv_.notify_all();
  }
}

void Server::stop_http() {
  {
    std::lock_guard lock(http_mu_);
    http_quit_ = true;
  }
  http_cv_.notify_all();
  if (http_thread_.joinable()) http_thread_.join();
}

// On civetweb's workers. A connection's address and port are known when it is opened; its
// request (and with it the token) only when begin_request runs.
void Server::on_connection_open(const mg_connection* conn) {
  const std::ptrdiff_t offset = request_info_offset_.load();
  if (offset < 0) return;  // before the first request: not counted
  const auto* ri =
      reinterpret_cast<const mg_request_info*>(reinterpret_cast<const char*>(conn) + offset);
  const std::string address(ri->remote_addr, strnlen(ri->remote_addr, sizeof ri->remote_addr));
  if (!address.empty()) limits_.opened(conn, address, ri->remote_port);
}

void Server::learn_request_info_offset() {
  // A request to ourselves (refused 403: no token), read to its end; its begin_request sets
  // the offset.
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port_));
  inet_pton(AF_INET, "127.0.0.1", &a.sin_addr);
  if (fd >= 0 && connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0) {
    const std::string req =
        fmt::format("GET / HTTP/1.1\r\nHost: 127.0.0.1:{}\r\nConnection: close\r\n\r\n", port_);
    (void)send(fd, req.data(), req.size(), MSG_NOSIGNAL);
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    char buf[1024];
    while (std::chrono::steady_clock::now() < end) {
      pollfd p{fd, POLLIN, 0};
      if (poll(&p, 1, 50) == 1 && recv(fd, buf, sizeof buf, 0) <= 0) break;
    }
  }
  if (fd >= 0) close(fd);
}

void Server::trim_loop() {
  std::unique_lock lock(trim_mu_);
  while (!trim_cv_.wait_for(lock, std::chrono::milliseconds(50), [this] { return trim_quit_; }))
    limits_.trim();
}

void Server::on_request(const mg_connection* conn) {
  if (request_info_offset_.load() < 0) {
    const auto d = reinterpret_cast<const char*>(mg_get_request_info(conn)) -
                   reinterpret_cast<const char*>(conn);
    if (d >= 0 && d < 65536) request_info_offset_ = d;
  }
  limits_.arrived(conn);
}

void Server::on_connection_close(const mg_connection* conn) {
  limits_.closed(conn);
}

int Server::on_http(mg_connection* conn) {
  return hand_over(conn, false);
}

int Server::serve_http(mg_connection* conn) {
  const mg_request_info* ri = mg_get_request_info(conn);
  if (!allowed(conn, false)) {
    send_text(conn, 403, "Forbidden", "403 forbidden: open the URL inhap studio printed\n");
    return 403;
  }
  if (std::string(ri->request_method) != "GET") {
    send_text(conn, 405, "Method Not Allowed", "405\n");
    return 405;
  }
  const auto it = routes().find(ri->local_uri ? ri->local_uri : "");
  if (it == routes().end()) {
    send_text(conn, 404, "Not Found", "404 not found\n");
    return 404;
  }
  const std::string body = slurp(fs::path(web_dir_) / it->second.first);
  // The cookie lets the page's module imports (which carry no query) through.
  const std::string cookie =
      fmt::format("Set-Cookie: {}={}; HttpOnly; SameSite=Strict; Path=/\r\n", kCookieName, token_);
  send_text(conn, 200, "OK", body, it->second.second.c_str(), cookie);
  return 200;
}

int Server::on_ws_connect(const mg_connection* conn) {
  // non-zero: refused
  return hand_over(const_cast<mg_connection*>(conn), true);
}

void Server::on_ws_ready(mg_connection* conn) {
  std::lock_guard lock(mu_);
  if (closing_all_) return;
  auto c = std::make_unique<Client>();
  c->conn = conn;
  Client* raw = c.get();
  c->writer = std::thread([this, raw] { write_loop(raw); });
  clients_[conn] = std::move(c);
}

int Server::on_ws_data(mg_connection* conn, int bits, char* data, std::size_t len) {
  const int opcode = bits & 0x0f;
  if (opcode == MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE) return 0;
  if (opcode != MG_WEBSOCKET_OPCODE_TEXT) return 1;  // pings are answered by civetweb
  {
    std::lock_guard lock(mu_);
    if (quit_) return 1;  // stopping
    const auto it = clients_.find(conn);
    if (it == clients_.end()) return 1;
    Client& c = *it->second;
    if (c.backlog >= kPageBacklog || queue_.size() >= kBacklog) {  // a burst: say so
      ++busy_;
      enqueue(c, error_reply("?", fmt::format("busy: {} messages of this page are waiting; this "
                                              "one was not run, send it again later",
                                              c.backlog)));
      return 1;
    }
    ++c.backlog;
    queue_.emplace_back(conn, std::string(data, len));
  }
  queue_cv_.notify_one();
  return 1;
}

void Server::work() {
  for (;;) {
    std::pair<mg_connection*, std::string> item;
    Handler h;
    {
      std::unique_lock lock(mu_);
      queue_cv_.wait(lock, [this] { return quit_ || !queue_.empty(); });
      if (quit_) return;
      item = std::move(queue_.front());
      queue_.pop_front();
      if (const auto it = clients_.find(item.first); it != clients_.end() && it->second->backlog)
        --it->second->backlog;
      h = handler_;
    }
    std::string reply;
    try {  // the handler never throws; this thread must not end if it ever did
      reply = h ? h(item.second) : error_reply("?", "the studio is starting, try again");
    } catch (...) {
      reply = error_reply("?", "internal error");
    }
    if (!reply.empty()) send_to(item.first, reply);
  }
}

void Server::enqueue(Client& c, const std::string& text) {
  if (c.closing) return;
  if (c.out.size() >= kSendQueue) {  // the oldest state goes first: the next one replaces it
    auto victim = std::find_if(c.out.begin(), c.out.end(), [](const std::string& m) {
      return m.rfind(R"({"type":"state")", 0) == 0;
    });
    c.out.erase(victim != c.out.end() ? victim : c.out.begin());
    ++c.dropped;
  }
  c.out.push_back(text);
  c.cv.notify_one();
}

void Server::write_loop(Client* c) {
  std::unique_lock lock(mu_);
  for (;;) {
    c->cv.wait(lock, [c] { return c->closing || !c->out.empty(); });
    if (c->closing) return;
    std::string text = std::move(c->out.front());
    c->out.pop_front();
    std::string note;
    if (c->dropped != c->dropped_told) {
      note = fmt::format(R"({{"type":"dropped","count":{}}})", c->dropped);
      c->dropped_told = c->dropped;
    }
    lock.unlock();  // a slow page blocks here, in its own thread only
    if (!note.empty())
      mg_websocket_write(c->conn, MG_WEBSOCKET_OPCODE_TEXT, note.data(), note.size());
    mg_websocket_write(c->conn, MG_WEBSOCKET_OPCODE_TEXT, text.data(), text.size());
    lock.lock();
  }
}

void Server::send_to(const mg_connection* conn, const std::string& text) {
  std::lock_guard lock(mu_);
  if (const auto it = clients_.find(conn); it != clients_.end()) enqueue(*it->second, text);
}

void Server::on_ws_close(const mg_connection* conn) {
  std::unique_ptr<Client> c;
  {
    std::lock_guard lock(mu_);
    const auto it = clients_.find(conn);
    if (it == clients_.end()) return;
    c = std::move(it->second);
    clients_.erase(it);
    c->closing = true;
    c->cv.notify_one();
  }
  if (c->writer.joinable()) c->writer.join();  // a write in progress ends within its time-out
}

void Server::close_clients() {
  std::map<const mg_connection*, std::unique_ptr<Client>> all;
  {
    std::lock_guard lock(mu_);
    closing_all_ = true;
    all.swap(clients_);
    for (auto& [conn, c] : all) {
      c->closing = true;
      c->cv.notify_one();
    }
  }
  for (auto& [conn, c] : all)
    if (c->writer.joinable()) c->writer.join();
}

void Server::broadcast(const std::string& text) {
  std::lock_guard lock(mu_);
  for (auto& [conn, c] : clients_) enqueue(*c, text);
}

}  // namespace inhap::studio
