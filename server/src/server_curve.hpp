// ZeroMQ CURVE authentication for remote use (issue 14 item 7): a server key pair and an
// allow-list of client public keys, read from a directory; a ZAP handler that admits only the
// listed clients; the loopback rule (a non-loopback endpoint needs keys unless insecure).
// ZeroMQ stays in the .cpp.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace zmq {
class context_t;
class socket_t;
} // namespace zmq

namespace polycut::server {

/// The files of a --curve-keys directory (Z85 text, 40 characters, one key per line):
///   server.public, server.secret   the server's key pair
///   authorized_clients             client public keys allowed in, one per line ('#' comments)
struct CurveKeys {
    std::string server_public; ///< Z85
    std::string server_secret; ///< Z85
    std::vector<std::string> authorized; ///< Z85 client public keys
};

/// Reads a key directory. Throws polycut::FileError naming the file and line on a missing file
/// or a key that is not 40 Z85 characters.
CurveKeys read_curve_keys(const std::string& dir);

/// A new Z85 key pair (public, secret).
std::pair<std::string, std::string> curve_keypair();

/// Writes a fresh server key pair and one client key pair into `dir` (created if needed):
/// server.public, server.secret, client.public, client.secret, and authorized_clients listing
/// the client's public key (appended if the file exists). Returns the client's key pair.
std::pair<std::string, std::string> write_curve_keys(const std::string& dir);

/// True for endpoints only this machine can reach: tcp://127.x.x.x, tcp://localhost,
/// tcp://[::1], ipc://, inproc://.
bool is_loopback_endpoint(const std::string& endpoint);

/// Makes `socket` a CURVE server with the key pair, under the ZAP domain "polycut".
void make_curve_server(zmq::socket_t& socket, const CurveKeys& keys);

/// The ZAP handler (RFC 27) on its own thread: admits CURVE clients whose public key is in the
/// allow-list and refuses everyone else (status 400). Stops and joins on destruction.
class ZapHandler {
public:
    ZapHandler(zmq::context_t& context, std::vector<std::string> authorized_z85);
    ~ZapHandler();
    ZapHandler(const ZapHandler&) = delete;
    ZapHandler& operator=(const ZapHandler&) = delete;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

} // namespace polycut::server
