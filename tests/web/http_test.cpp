// The small HTTP server of `grip view`: request lines, GET only, files streamed, on loopback.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <thread>

#include "core/error.hpp"
#include "web/http.hpp"

namespace grip::web {
namespace {

TEST(Http, ParsesRequestLines) {
  auto r = parseRequestLine("GET /recording.jsonl HTTP/1.1\r\nHost: x\r\n\r\n");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->method, "GET");
  EXPECT_EQ(r->path, "/recording.jsonl");
  EXPECT_EQ(r->query, "");
  r = parseRequestLine("GET /?url=recording.jsonl HTTP/1.0\r\n\r\n");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->path, "/");
  EXPECT_EQ(r->query, "url=recording.jsonl");
  for (const char* bad : {"", "GET", "GET /", "GET / FTP/1.0\r\n", "GET x HTTP/1.1\r\n",
                          " / HTTP/1.1\r\n", "GET  HTTP/1.1\r\n"})
    EXPECT_FALSE(parseRequestLine(bad)) << bad;
}

// Sends raw bytes to 127.0.0.1:port, returns everything the server answers.
std::string exchange(int port, const std::string& request) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  EXPECT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  EXPECT_EQ(::send(fd, request.data(), request.size(), 0), static_cast<ssize_t>(request.size()));
  std::string out;
  char buf[4096];
  ssize_t k = 0;
  while ((k = ::recv(fd, buf, sizeof buf, 0)) > 0) out.append(buf, static_cast<size_t>(k));
  ::close(fd);
  return out;
}

TEST(Http, ServesGetOnlyAndStreamsFiles) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "grip_http_test.txt";
  std::string content(200000, 'x');  // larger than one send
  for (size_t i = 0; i < content.size(); i += 7) content[i] = static_cast<char>('a' + i % 26);
  std::ofstream(file, std::ios::binary) << content;

  Server server(0);
  ASSERT_GT(server.port(), 0);
  std::atomic<bool> stop{false};
  std::atomic<int> handled{0};
  std::thread t([&] {
    server.serve(
        [&](const Request& r) -> Response {
          ++handled;
          if (r.path == "/file") return {200, "text/plain", "", file.string()};
          if (r.path == "/") return {200, "text/html", "<p>" + r.query + "</p>", ""};
          return {404, "text/plain", "not found\n", ""};
        },
        [&] { return stop.load(); });
  });
  std::string r = exchange(server.port(), "GET /?a=1 HTTP/1.1\r\nHost: x\r\n\r\n");
  EXPECT_EQ(r.substr(0, r.find("\r\n")), "HTTP/1.1 200 OK");
  EXPECT_NE(r.find("Content-Length: 10\r\n"), std::string::npos);
  EXPECT_EQ(r.substr(r.find("\r\n\r\n") + 4), "<p>a=1</p>");
  r = exchange(server.port(), "GET /file HTTP/1.1\r\n\r\n");
  EXPECT_NE(r.find("Content-Length: 200000\r\n"), std::string::npos);
  EXPECT_EQ(r.substr(r.find("\r\n\r\n") + 4), content);
  r = exchange(server.port(), "GET /nope HTTP/1.1\r\n\r\n");
  EXPECT_EQ(r.substr(0, r.find("\r\n")), "HTTP/1.1 404 Not Found");
  const int before = handled.load();
  r = exchange(server.port(), "POST / HTTP/1.1\r\nContent-Length: 0\r\n\r\n");
  EXPECT_EQ(r.substr(0, r.find("\r\n")), "HTTP/1.1 405 Method Not Allowed");
  EXPECT_NE(r.find("Allow: GET\r\n"), std::string::npos);
  r = exchange(server.port(), "hello\r\n\r\n");
  EXPECT_EQ(r.substr(0, r.find("\r\n")), "HTTP/1.1 400 Bad Request");
  EXPECT_EQ(handled.load(), before);  // neither reached the handler
  stop = true;
  t.join();
  std::filesystem::remove(file);
}

TEST(Http, ABusyPortIsAClearError) {
  Server first(0);
  try {
    Server second(first.port());
    ADD_FAILURE() << "bound twice";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot listen: Address already in use (choose another "
                                         "port with --port)"),
              std::string::npos);
  }
  EXPECT_THROW(Server(70000), Error);
}

}  // namespace
}  // namespace grip::web
