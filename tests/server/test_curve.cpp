// CURVE authentication (issue 14 item 7): with --curve-keys a client in authorized_clients gets
// in and reads an encrypted stream; an unknown key or a plain client gets nothing; without keys
// a non-loopback endpoint is refused at start-up unless insecure.
#include "polycut/common/error.hpp"
#include "server_curve.hpp"
#include "server_fixture.hpp"

namespace polycut::server::testing {
namespace {

using namespace protocol;

class Curve : public ::testing::Test {
protected:
    SceneDir dir;
    zmq::context_t context { 1 };
    std::string keys_dir() const { return dir.file("keys"); }

    /// A DEALER (or SUB) speaking CURVE with the given client key pair.
    zmq::socket_t curve_socket(zmq::socket_type type, const std::string& endpoint,
        const std::pair<std::string, std::string>& client) {
        zmq::socket_t s(context, type);
        s.set(zmq::sockopt::linger, 0);
        s.set(zmq::sockopt::sndtimeo, kTestSendTimeoutMs);
        s.set(zmq::sockopt::curve_serverkey, read_curve_keys(keys_dir()).server_public);
        s.set(zmq::sockopt::curve_publickey, client.first);
        s.set(zmq::sockopt::curve_secretkey, client.second);
        s.connect(endpoint);
        return s;
    }
};

std::optional<Message> hello(zmq::socket_t& s, int timeout_ms) {
    if (!send_message(s, Message { R"({"jsonrpc":"2.0","id":1,"method":"hello"})" })) {
        return std::nullopt; // the handshake was refused: no pipe to send on
    }
    return recv_message(s, std::chrono::milliseconds(timeout_ms));
}

TEST_F(Curve, OnlyAuthorizedClientsGetInAndTheStreamIsEncrypted) {
    const auto allowed = write_curve_keys(keys_dir());
    ServerConfig c = test_config(dir, false);
    c.curve_keys = keys_dir();
    RunningServer server(c);

    zmq::socket_t ok = curve_socket(zmq::socket_type::dealer, server.control(), allowed);
    const auto reply = hello(ok, 5000);
    ASSERT_TRUE(reply.has_value());
    EXPECT_NE(reply->front().find("\"curve\""), std::string::npos) << reply->front();

    // A valid key pair that is not in authorized_clients: the handshake is refused.
    zmq::socket_t stranger
        = curve_socket(zmq::socket_type::dealer, server.control(), curve_keypair());
    EXPECT_FALSE(hello(stranger, 500).has_value());
    // A plain (NULL mechanism) client: nothing either.
    Client plain(context, server.control());
    EXPECT_FALSE(plain
                     .raw(Message { R"({"jsonrpc":"2.0","id":1,"method":"hello"})" },
                         std::chrono::milliseconds(500))
                     .has_value());

    // The stream: the authorized subscriber reads surface frames; a plain one reads nothing.
    zmq::socket_t sub = curve_socket(zmq::socket_type::sub, server.stream(), allowed);
    sub.set(zmq::sockopt::subscribe, "surface");
    zmq::socket_t plain_sub(context, zmq::socket_type::sub);
    plain_sub.set(zmq::sockopt::linger, 0);
    plain_sub.connect(server.stream());
    plain_sub.set(zmq::sockopt::subscribe, "");
    const auto frame = recv_message(sub, std::chrono::milliseconds(5000));
    ASSERT_TRUE(frame.has_value());
    EXPECT_EQ(frame->front(), "surface");
    EXPECT_FALSE(recv_message(plain_sub, std::chrono::milliseconds(500)).has_value());
}

TEST_F(Curve, ANonLoopbackEndpointNeedsKeysOrInsecure) {
    ServerConfig c = test_config(dir, true);
    c.control = "tcp://0.0.0.0:*";
    EXPECT_THROW(Server { c }, InputError);
    c.control = "tcp://127.0.0.1:*";
    c.stream = "tcp://*:*";
    EXPECT_THROW(Server { c }, InputError);
    c.insecure = true;
    EXPECT_NO_THROW(Server { c });
    write_curve_keys(keys_dir());
    c.insecure = false;
    c.curve_keys = keys_dir();
    EXPECT_NO_THROW(Server { c });
    EXPECT_TRUE(is_loopback_endpoint("tcp://127.0.0.1:5555"));
    EXPECT_TRUE(is_loopback_endpoint("tcp://localhost:5555"));
    EXPECT_TRUE(is_loopback_endpoint("ipc:///tmp/polycut"));
    EXPECT_FALSE(is_loopback_endpoint("tcp://10.0.0.5:5555"));
    EXPECT_FALSE(is_loopback_endpoint("tcp://eth0:5555"));
}

TEST_F(Curve, ABadKeyFileIsAnErrorNamingTheFileAndLine) {
    write_curve_keys(keys_dir());
    std::ofstream(dir.file("keys/authorized_clients"), std::ios::app) << "# fine\nnot-a-key\n";
    try {
        read_curve_keys(keys_dir());
        FAIL() << "a bad key was accepted";
    } catch (const FileError& e) {
        EXPECT_NE(e.path().find("authorized_clients"), std::string::npos);
        EXPECT_EQ(e.line(), 3);
    }
}

} // namespace
} // namespace polycut::server::testing
