#include "hostile_wire.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>
#include <regex>
#include <sstream>

namespace ddsimp::load {

RawConnection::RawConnection(const std::string& host, uint16_t port, const std::string& from) {
    addrinfo hints{};
    hints.ai_family = AF_INET;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    if (::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found) != 0) return;
    fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    bool ok = fd_ >= 0;
    if (ok && !from.empty()) {
        sockaddr_in local{};
        local.sin_family = AF_INET;
        ok = ::inet_pton(AF_INET, from.c_str(), &local.sin_addr) == 1 &&
             ::bind(fd_, reinterpret_cast<sockaddr*>(&local), sizeof local) == 0;
    }
    ok = ok && ::connect(fd_, found->ai_addr, found->ai_addrlen) == 0;
    ::freeaddrinfo(found);
    if (!ok && fd_ >= 0) {
        ::close(fd_);
        fd_ = -1;
    }
    if (ok) {
        const int one = 1;
        ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    }
}

RawConnection::~RawConnection() {
    if (fd_ >= 0) ::close(fd_);
}

bool RawConnection::send_bytes(const std::string& bytes) {
    size_t done = 0;
    while (fd_ >= 0 && done < bytes.size()) {
        const ssize_t n = ::send(fd_, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
        if (n <= 0) return false;
        done += size_t(n);
    }
    return fd_ >= 0;
}

std::optional<protocol::Frame> RawConnection::next() {
    char buffer[64 << 10];
    while (fd_ >= 0) {
        try {
            if (auto f = decoder_.next()) return f;
        } catch (const protocol::FrameError&) {
            return std::nullopt;
        }
        const ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0);
        if (n <= 0) return std::nullopt;
        decoder_.feed(std::string_view(buffer, size_t(n)));
    }
    return std::nullopt;
}

bool RawConnection::receive(std::string& out) {
    char buffer[64 << 10];
    const ssize_t n = fd_ >= 0 ? ::recv(fd_, buffer, sizeof buffer, 0) : -1;
    if (n <= 0) return false;
    out.append(buffer, size_t(n));
    return true;
}

bool RawConnection::closed_by_server() const {
    if (fd_ < 0) return true;
    pollfd p{fd_, POLLIN | POLLRDHUP, 0};
    if (::poll(&p, 1, 0) <= 0) return false;
    if (p.revents & (POLLRDHUP | POLLHUP | POLLERR)) return true;
    char ch;
    return ::recv(fd_, &ch, 1, MSG_PEEK | MSG_DONTWAIT) == 0;
}

void RawConnection::shut_down() {
    if (fd_ >= 0) ::shutdown(fd_, SHUT_RDWR);
}

bool RawConnection::handshake(const std::string& client_name, const std::string& token) {
    v1::Hello hello;
    hello.set_protocol_version(protocol::kProtocolVersion);
    hello.set_client_name(client_name);
    hello.set_kind(v1::TOOL);
    hello.add_capabilities("sessions");
    if (!send(hello)) return false;
    const std::optional<protocol::Frame> welcome = next();
    if (!welcome || welcome->type != v1::WELCOME) return false;
    if (!protocol::parse_payload<v1::Welcome>(*welcome).auth_required()) return true;
    v1::Auth auth;
    auth.set_token(token);
    if (!send(auth)) return false;
    const std::optional<protocol::Frame> ok = next();
    return ok && ok->type == v1::AUTH_OK;
}

HttpKeepAlive::HttpKeepAlive(const std::string& host, uint16_t port) : host_(host), port_(port) {}

std::optional<std::string> HttpKeepAlive::get(const std::string& target) {
    for (int attempt = 0; attempt < 2; ++attempt) {
        if (!connection_ || !connection_->connected() || connection_->closed_by_server()) {
            connection_.emplace(host_, port_);
            buffer_.clear();
        }
        if (!connection_->send_bytes("GET " + target + " HTTP/1.1\r\nHost: " + host_ + "\r\n\r\n"))
            continue;
        size_t head_end;
        while ((head_end = buffer_.find("\r\n\r\n")) == std::string::npos)
            if (!connection_->receive(buffer_)) break;
        if (head_end == std::string::npos) continue;
        head_end += 4;
        std::smatch m;
        const std::string head = buffer_.substr(0, head_end);
        if (!std::regex_search(head, m, std::regex("Content-Length: *([0-9]+)", std::regex::icase)))
            return std::nullopt;
        const size_t length = std::stoul(m[1]);
        while (buffer_.size() < head_end + length)
            if (!connection_->receive(buffer_)) break;
        if (buffer_.size() < head_end + length) continue;
        std::string body = buffer_.substr(head_end, length);
        buffer_.erase(0, head_end + length);
        return body;
    }
    return std::nullopt;
}

std::map<std::string, double> parse_metrics(const std::string& text) {
    std::map<std::string, double> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        const size_t space = line.rfind(' ');
        if (space == std::string::npos) continue;
        try {
            out[line.substr(0, space)] = std::stod(line.substr(space + 1));
        } catch (const std::exception&) {
        }
    }
    return out;
}

} // namespace ddsimp::load
