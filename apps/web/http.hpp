// A small HTTP/1.1 server on 127.0.0.1 for `grip view`: GET only, one request at a time,
// every connection closed after its response. Enough for one browser on the same machine.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>

namespace grip::web {

struct Request {
  std::string method;
  std::string path;   // without the query
  std::string query;  // after '?', may be empty
};

// The request line of a request head ("GET /x?y HTTP/1.1\r\n..."); nullopt when malformed.
std::optional<Request> parseRequestLine(std::string_view head);

struct Response {
  int status = 200;
  std::string contentType = "text/plain; charset=utf-8";
  std::string body;
  std::string file;  // when set, the body is this file's content (streamed)
};

// The status line's reason phrase ("Not Found").
const char* reasonPhrase(int status);

class Server {
 public:
  // Listens on 127.0.0.1:port (0: a free port). Throws grip::Error when it cannot.
  explicit Server(int port);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;
  int port() const { return port_; }
  // Answers requests until stop() returns true (it is polled at least every 200 ms).
  // Requests other than GET get 405 without calling the handler.
  void serve(const std::function<Response(const Request&)>& handler,
             const std::function<bool()>& stop);

 private:
  int fd_ = -1;
  int port_ = 0;
};

}  // namespace grip::web
