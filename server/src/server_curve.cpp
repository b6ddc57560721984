// CURVE keys, the loopback rule and the ZAP allow-list handler (server_curve.hpp).
#include "server_curve.hpp"

#include "polycut/common/error.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>
#include <zmq.hpp>

namespace polycut::server {

namespace {

constexpr std::size_t kZ85KeyLength = 40;

bool is_z85_key(const std::string& key) {
    std::array<std::uint8_t, 32> bin {};
    return key.size() == kZ85KeyLength && zmq_z85_decode(bin.data(), key.c_str()) != nullptr;
}

/// The keys of a file, one per line; blank lines and '#' comments skipped.
std::vector<std::string> read_keys(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) {
        throw FileError(path.string(), 0, "cannot be read");
    }
    std::vector<std::string> keys;
    std::string line;
    long number = 0;
    while (std::getline(in, line)) {
        ++number;
        line.erase(0, line.find_first_not_of(" \t\r"));
        line.erase(line.find_last_not_of(" \t\r") + 1);
        if (line.empty() || line.front() == '#') {
            continue;
        }
        if (!is_z85_key(line)) {
            throw FileError(path.string(), number, "not a Z85 CURVE key (40 characters)");
        }
        keys.push_back(line);
    }
    return keys;
}

std::string read_one_key(const std::filesystem::path& path) {
    const auto keys = read_keys(path);
    if (keys.size() != 1) {
        throw FileError(path.string(), 0, "must hold exactly one key");
    }
    return keys.front();
}

} // namespace

CurveKeys read_curve_keys(const std::string& dir) {
    const std::filesystem::path d(dir);
    CurveKeys k;
    k.server_public = read_one_key(d / "server.public");
    k.server_secret = read_one_key(d / "server.secret");
    k.authorized = read_keys(d / "authorized_clients");
    return k;
}

std::pair<std::string, std::string> curve_keypair() {
    std::array<char, 41> pub {}, sec {};
    if (zmq_curve_keypair(pub.data(), sec.data()) != 0) {
        throw std::runtime_error("zmq_curve_keypair failed (libzmq without CURVE?)");
    }
    return { std::string(pub.data()), std::string(sec.data()) };
}

std::pair<std::string, std::string> write_curve_keys(const std::string& dir) {
    const std::filesystem::path d(dir);
    std::filesystem::create_directories(d);
    const auto [server_pub, server_sec] = curve_keypair();
    const auto client = curve_keypair();
    std::ofstream(d / "server.public") << server_pub << "\n";
    std::ofstream(d / "server.secret") << server_sec << "\n";
    std::ofstream(d / "client.public") << client.first << "\n";
    std::ofstream(d / "client.secret") << client.second << "\n";
    std::ofstream(d / "authorized_clients", std::ios::app) << client.first << "\n";
    std::filesystem::permissions(d / "server.secret",
        std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
    std::filesystem::permissions(d / "client.secret",
        std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
    return client;
}

bool is_loopback_endpoint(const std::string& endpoint) {
    if (endpoint.rfind("ipc://", 0) == 0 || endpoint.rfind("inproc://", 0) == 0) {
        return true;
    }
    if (endpoint.rfind("tcp://", 0) != 0) {
        return false;
    }
    const std::string host = endpoint.substr(6, endpoint.rfind(':') - 6);
    return host.rfind("127.", 0) == 0 || host == "localhost" || host == "[::1]";
}

void make_curve_server(zmq::socket_t& socket, const CurveKeys& keys) {
    socket.set(zmq::sockopt::zap_domain, "polycut");
    socket.set(zmq::sockopt::curve_server, 1);
    socket.set(zmq::sockopt::curve_secretkey, keys.server_secret);
}

struct ZapHandler::Impl {
    zmq::socket_t socket;
    std::set<std::string> authorized; ///< binary public keys (32 bytes)
    std::atomic<bool> stop { false };
    std::thread thread;

    Impl(zmq::context_t& context, const std::vector<std::string>& z85)
        : socket(context, zmq::socket_type::rep) {
        for (const std::string& key : z85) {
            std::array<std::uint8_t, 32> bin {};
            zmq_z85_decode(bin.data(), key.c_str());
            authorized.emplace(reinterpret_cast<const char*>(bin.data()), bin.size());
        }
        socket.set(zmq::sockopt::linger, 0);
        socket.bind("inproc://zeromq.zap.01");
        thread = std::thread([this] { run(); });
    }

    void run() {
        while (!stop.load()) {
            zmq::pollitem_t item { socket.handle(), 0, ZMQ_POLLIN, 0 };
            try {
                zmq::poll(&item, 1, std::chrono::milliseconds(50));
                if ((item.revents & ZMQ_POLLIN) == 0) {
                    continue;
                }
                std::vector<std::string> frames;
                bool more = true;
                while (more) {
                    zmq::message_t part;
                    (void)socket.recv(part, zmq::recv_flags::none);
                    frames.emplace_back(part.data<char>(), part.size());
                    more = part.more();
                }
                answer(frames);
            } catch (const zmq::error_t& e) {
                if (e.num() == ETERM) {
                    return;
                }
            }
        }
    }

    /// RFC 27: version, request id, domain, address, identity, mechanism, credentials...
    void answer(const std::vector<std::string>& f) {
        const bool well_formed = f.size() >= 6 && f[0] == "1.0";
        const bool admitted
            = well_formed && f[5] == "CURVE" && f.size() >= 7 && authorized.count(f[6]) > 0;
        const std::string request_id = f.size() > 1 ? f[1] : std::string();
        const std::array<std::string, 6> reply { "1.0", request_id, admitted ? "200" : "400",
            admitted ? "OK" : "client key not authorized", admitted ? "client" : "", "" };
        for (std::size_t k = 0; k < reply.size(); ++k) {
            socket.send(zmq::buffer(reply[k]),
                k + 1 < reply.size() ? zmq::send_flags::sndmore : zmq::send_flags::none);
        }
    }
};

ZapHandler::ZapHandler(zmq::context_t& context, std::vector<std::string> authorized_z85)
    : m_impl(std::make_unique<Impl>(context, authorized_z85)) { }

ZapHandler::~ZapHandler() {
    m_impl->stop.store(true);
    if (m_impl->thread.joinable()) {
        m_impl->thread.join();
    }
}

} // namespace polycut::server
