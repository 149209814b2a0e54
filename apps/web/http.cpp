// POSIX sockets: socket/bind/listen on loopback, poll so that Ctrl-C is noticed, send with
// MSG_NOSIGNAL so that a browser closing early cannot kill the process with SIGPIPE.
#include "web/http.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "core/error.hpp"

namespace grip::web {

namespace {

bool sendAll(int fd, const char* data, size_t n) {
  while (n > 0) {
    const ssize_t k = ::send(fd, data, n, MSG_NOSIGNAL);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    data += k;
    n -= static_cast<size_t>(k);
  }
  return true;
}

void respond(int fd, const Response& r) {
  std::FILE* file = nullptr;
  long long length = static_cast<long long>(r.body.size());
  Response actual = r;
  if (!r.file.empty()) {
    file = std::fopen(r.file.c_str(), "rb");
    if (!file || std::fseek(file, 0, SEEK_END) != 0 || (length = std::ftell(file)) < 0) {
      if (file) std::fclose(file);
      file = nullptr;
      actual = Response{500, "text/plain; charset=utf-8", "cannot read " + r.file + "\n", ""};
      length = static_cast<long long>(actual.body.size());
    } else {
      std::rewind(file);
    }
  }
  char head[512];
  const int n =
      std::snprintf(head, sizeof head,
                    "HTTP/1.1 %d %s\r\nContent-Type: %s\r\nContent-Length: %lld\r\n"
                    "Cache-Control: no-store\r\n%sConnection: close\r\n\r\n",
                    actual.status, reasonPhrase(actual.status), actual.contentType.c_str(), length,
                    actual.status == 405 ? "Allow: GET\r\n" : "");
  bool ok = sendAll(fd, head, static_cast<size_t>(n));
  if (file) {
    char buf[1 << 16];
    size_t k = 0;
    while (ok && (k = std::fread(buf, 1, sizeof buf, file)) > 0) ok = sendAll(fd, buf, k);
    std::fclose(file);
  } else if (ok) {
    sendAll(fd, actual.body.data(), actual.body.size());
  }
}

}  // namespace

std::optional<Request> parseRequestLine(std::string_view head) {
  const size_t eol = head.find("\r\n");
  const std::string_view line = head.substr(0, eol);
  const size_t a = line.find(' ');
  if (a == std::string_view::npos || a == 0) return std::nullopt;
  const size_t b = line.find(' ', a + 1);
  if (b == std::string_view::npos || b == a + 1) return std::nullopt;
  if (line.substr(b + 1).rfind("HTTP/1.", 0) != 0) return std::nullopt;
  Request r;
  r.method = std::string(line.substr(0, a));
  const std::string_view target = line.substr(a + 1, b - a - 1);
  if (target.front() != '/') return std::nullopt;
  const size_t q = target.find('?');
  r.path = std::string(target.substr(0, q));
  if (q != std::string_view::npos) r.query = std::string(target.substr(q + 1));
  return r;
}

const char* reasonPhrase(int status) {
  switch (status) {
    case 200:
      return "OK";
    case 400:
      return "Bad Request";
    case 404:
      return "Not Found";
    case 405:
      return "Method Not Allowed";
    case 431:
      return "Request Header Fields Too Large";
    default:
      return "Internal Server Error";
  }
}

Server::Server(int port) {
  if (port < 0 || port > 65535)
    throw Error("--port", "must be in 0..65535 (got " + std::to_string(port) + ")");
  fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) throw Error("socket", std::strerror(errno));
  const int yes = 1;
  ::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 || ::listen(fd_, 16) != 0) {
    const int err = errno;
    ::close(fd_);
    throw Error("127.0.0.1:" + std::to_string(port),
                std::string("cannot listen: ") + std::strerror(err) +
                    (err == EADDRINUSE ? " (choose another port with --port)" : ""));
  }
  socklen_t len = sizeof addr;
  ::getsockname(fd_, reinterpret_cast<sockaddr*>(&addr), &len);
  port_ = ntohs(addr.sin_port);
}

Server::~Server() {
  if (fd_ >= 0) ::close(fd_);
}

void Server::serve(const std::function<Response(const Request&)>& handler,
                   const std::function<bool()>& stop) {
  while (!stop()) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, 200) <= 0) continue;  // a timeout, or a signal: check stop()
    const int c = ::accept4(fd_, nullptr, nullptr, SOCK_CLOEXEC);
    if (c < 0) continue;
    timeval tv{2, 0};  // a client that sends nothing does not hold the server
    ::setsockopt(c, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    std::string head;
    char buf[2048];
    while (head.find("\r\n\r\n") == std::string::npos && head.size() < 16384) {
      const ssize_t k = ::recv(c, buf, sizeof buf, 0);
      if (k <= 0) break;
      head.append(buf, static_cast<size_t>(k));
    }
    const std::optional<Request> r = parseRequestLine(head);
    if (head.find("\r\n\r\n") == std::string::npos && head.size() >= 16384) {
      respond(c, {431, "text/plain; charset=utf-8", "request head too large\n", ""});
    } else if (!r) {
      if (!head.empty()) respond(c, {400, "text/plain; charset=utf-8", "bad request\n", ""});
    } else if (r->method != "GET") {
      respond(c, {405, "text/plain; charset=utf-8", "only GET is served\n", ""});
    } else {
      respond(c, handler(*r));
    }
    ::close(c);
  }
}

}  // namespace grip::web
