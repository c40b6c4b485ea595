#include "hostile_wire.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <openssl/err.h>
#include <openssl/ssl.h>

#include <fcntl.h>

#include <cstring>
#include <mutex>
#include <regex>
#include <sstream>

namespace ddsimp::load {
namespace {

std::atomic<bool> g_tls{false};

SSL_CTX* client_context() {
    static SSL_CTX* context = [] {
        SSL_CTX* c = SSL_CTX_new(TLS_client_method());
        SSL_CTX_set_verify(c, SSL_VERIFY_NONE, nullptr);
        SSL_CTX_set_mode(c, SSL_MODE_ENABLE_PARTIAL_WRITE | SSL_MODE_ACCEPT_MOVING_WRITE_BUFFER);
        return c;
    }();
    return context;
}

} // namespace

void use_tls(bool on) {
    g_tls = on;
}
bool tls_in_use() {
    return g_tls;
}

// One SSL object used by a reader and a writer thread: every call under the mutex, on a
// non-blocking socket, waiting in poll() outside it.
struct RawConnection::Tls {
    SSL* ssl = nullptr;
    std::mutex mutex;
    bool started = false, ready = false, failed = false;
    ~Tls() {
        if (ssl) SSL_free(ssl);
    }
};

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
        if (g_tls) {
            tls_ = std::make_unique<Tls>();
            tls_->ssl = SSL_new(client_context());
            SSL_set_fd(tls_->ssl, fd_);
            SSL_set_connect_state(tls_->ssl);
            ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) | O_NONBLOCK);
        }
    }
}

RawConnection::~RawConnection() {
    tls_.reset();
    if (fd_ >= 0) ::close(fd_);
}

bool RawConnection::start_tls_handshake_only() {
    if (!tls_ || fd_ < 0) return false;
    std::lock_guard lock(tls_->mutex);
    if (tls_->started) return false;
    tls_->started = true;
    // Non-blocking: writes the ClientHello, then would wait for the server's answer.
    const int r = SSL_do_handshake(tls_->ssl);
    return r == 1 || SSL_get_error(tls_->ssl, r) == SSL_ERROR_WANT_READ;
}

namespace {

// Waits until `fd` is ready for what OpenSSL asked (`error`), up to 100 ms.
void wait_for(int fd, int error) {
    pollfd p{fd, short(error == SSL_ERROR_WANT_WRITE ? POLLOUT : POLLIN), 0};
    ::poll(&p, 1, 100);
}

} // namespace

ssize_t RawConnection::read_some(char* buffer, size_t size) {
    if (fd_ < 0) return -1;
    if (!tls_) return ::recv(fd_, buffer, size, 0);
    for (;;) {
        if (shut_) return -1;
        int error = 0;
        {
            std::lock_guard lock(tls_->mutex);
            if (tls_->failed) return -1;
            tls_->started = true;
            const int n = SSL_read(tls_->ssl, buffer, int(std::min<size_t>(size, 1 << 30)));
            if (n > 0) return n;
            error = SSL_get_error(tls_->ssl, n);
            if (error != SSL_ERROR_WANT_READ && error != SSL_ERROR_WANT_WRITE) {
                tls_->failed = true;
                ERR_clear_error();
                return -1;
            }
        }
        wait_for(fd_, error);
    }
}

bool RawConnection::write_all(const char* data, size_t size) {
    size_t done = 0;
    while (fd_ >= 0 && done < size) {
        if (!tls_) {
            const ssize_t n = ::send(fd_, data + done, size - done, MSG_NOSIGNAL);
            if (n <= 0) return false;
            done += size_t(n);
            continue;
        }
        if (shut_) return false;
        int error = 0;
        {
            std::lock_guard lock(tls_->mutex);
            if (tls_->failed) return false;
            tls_->started = true;
            const int n =
                SSL_write(tls_->ssl, data + done, int(std::min<size_t>(size - done, 1 << 30)));
            if (n > 0) {
                done += size_t(n);
                continue;
            }
            error = SSL_get_error(tls_->ssl, n);
            if (error != SSL_ERROR_WANT_READ && error != SSL_ERROR_WANT_WRITE) {
                tls_->failed = true;
                ERR_clear_error();
                return false;
            }
        }
        wait_for(fd_, error);
    }
    return fd_ >= 0;
}

bool RawConnection::send_bytes(const std::string& bytes) {
    return write_all(bytes.data(), bytes.size());
}

std::optional<protocol::Frame> RawConnection::next() {
    char buffer[64 << 10];
    while (fd_ >= 0) {
        try {
            if (auto f = decoder_.next()) return f;
        } catch (const protocol::FrameError&) {
            return std::nullopt;
        }
        const ssize_t n = read_some(buffer, sizeof buffer);
        if (n <= 0) return std::nullopt;
        decoder_.feed(std::string_view(buffer, size_t(n)));
    }
    return std::nullopt;
}

bool RawConnection::receive(std::string& out) {
    char buffer[64 << 10];
    const ssize_t n = read_some(buffer, sizeof buffer);
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
    shut_ = true;
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
