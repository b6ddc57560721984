// polycut-igtl: an OpenIGTLink server for 3D Slicer (OpenIGTLinkIF) in front of polycut-server
// (docs/slicer.md). It mirrors the streamed surface (Clone pattern) and sends it to every
// connected OpenIGTLink client as POLYDATA, at most `rate_hz` times a second and only when it
// changed; TRANSFORM messages drive tools: a device whose name contains "scalpel" or "blade" is
// a scalpel (each pose a `scalpel` sample of one stroke, the stroke ends after `idle_s` without
// poses), any other device a grab (the first pose grabs, later ones move the anchor, silence
// releases). One thread: zmq::poll over the ZeroMQ sockets and the TCP sockets.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>

namespace polycut::igtl_bridge {

/// Settings of polycut-igtl (lengths SI; the OpenIGTLink side uses mm_per_m).
struct BridgeOptions {
    std::string control = "tcp://127.0.0.1:5555"; ///< polycut-server's control endpoint
    std::string host = "127.0.0.1"; ///< OpenIGTLink listen address (loopback by default)
    int port = 18944; ///< OpenIGTLink port (18944 is Slicer's default); 0 = any free port
    std::string device = "polycut"; ///< device name of the POLYDATA messages
    double rate_hz = 30; ///< most POLYDATA messages per second per client [Hz]
    double mm_per_m = 1000; ///< OpenIGTLink length unit per metre (Slicer: mm)
    double blade_length = 0.03; ///< scalpel blade from the pose's origin along its local z [m]
    double grab_stiffness = 400; ///< [N/m]
    double idle_s = 0.3; ///< a tool without poses this long ends its stroke or grab [s]
    bool quiet = false;
};

/// What the bridge did (for the caller's summary).
struct BridgeSummary {
    long clients = 0; ///< OpenIGTLink clients accepted
    long polydata_sent = 0; ///< POLYDATA messages sent
    long transforms = 0; ///< TRANSFORM messages used
    long snapshots = 0; ///< get_surface snapshots (1 + resyncs)
};

/// Listens (throws polycut::Error when it cannot) and reports the bound port through
/// `on_listening`; then serves until `stop`.
BridgeSummary run_bridge(
    const BridgeOptions& options, const std::atomic<bool>& stop, void (*on_listening)(int port));

} // namespace polycut::igtl_bridge
