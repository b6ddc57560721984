// Live recording from the surface stream (see live_recorder.hpp).
#include "live_recorder.hpp"

#include "control_client.hpp"
#include "polycut/common/error.hpp"
#include "polycut/common/stats.hpp"

#include <condition_variable>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

namespace polycut::record {

namespace {

using Clock = std::chrono::steady_clock;

/// Triangles and tags of one topology version, shared by every frame that uses it.
struct Topology {
    std::uint64_t version = 0;
    std::vector<std::uint32_t> triangles;
    std::vector<std::uint8_t> tags;
};

/// A complete surface ready to render.
struct QueuedFrame {
    std::uint64_t seq = 0;
    std::int64_t tick = 0;
    std::shared_ptr<const Topology> topology;
    std::vector<float> positions;
};

/// The hand-over between the receiver thread and the renderer.
struct FrameQueue {
    std::mutex mutex;
    std::condition_variable ready;
    std::deque<QueuedFrame> frames;
    bool closed = false; ///< the receiver is done
    std::exception_ptr error; ///< why the receiver stopped, if it failed
};

/// The receiver: Clone-pattern state machine over the SUB and DEALER sockets.
class Receiver {
public:
    Receiver(const LiveOptions& options, const ServerInfo& server, FrameQueue& queue,
        const std::atomic<bool>& stop, const std::atomic<bool>& abort, LiveSummary& summary)
        : m_options(options)
        , m_server(server)
        , m_queue(queue)
        , m_stop(stop)
        , m_abort(abort)
        , m_summary(summary) { }

    void run() {
        zmq::context_t context(1);
        zmq::socket_t sub(context, zmq::socket_type::sub);
        sub.set(zmq::sockopt::linger, 0);
        sub.set(zmq::sockopt::rcvhwm, 100000); // we drain continuously; never drop here
        sub.connect(m_server.stream);
        sub.set(zmq::sockopt::subscribe, protocol::kSurfaceTopic);
        ControlClient control(context, m_options.server);

        request_snapshot(control);
        const auto start = Clock::now();
        while (!m_stop.load(std::memory_order_relaxed) && !m_abort.load() && !done()) {
            if (m_options.seconds > 0
                && std::chrono::duration<double>(Clock::now() - start).count()
                    >= m_options.seconds) {
                break;
            }
            zmq::pollitem_t items[] = { { sub.handle(), 0, ZMQ_POLLIN, 0 },
                { control.socket().handle(), 0, ZMQ_POLLIN, 0 } };
            zmq::poll(items, 2, std::chrono::milliseconds(50));
            if ((items[1].revents & ZMQ_POLLIN) != 0) {
                on_reply(control);
            }
            if ((items[0].revents & ZMQ_POLLIN) != 0) {
                for (int n = 0; n < 256 && !done(); ++n) {
                    zmq::pollitem_t again { sub.handle(), 0, ZMQ_POLLIN, 0 };
                    if (n > 0 && zmq::poll(&again, 1, std::chrono::milliseconds(0)) == 0) {
                        break;
                    }
                    on_stream(receive_message(sub), control);
                }
            }
            if (m_snapshot_id != 0 && Clock::now() > m_snapshot_deadline) {
                throw Error("get_surface",
                    "no snapshot from " + m_options.server + " within "
                        + std::to_string(m_options.reply_timeout_s) + " s");
            }
        }
    }

private:
    bool done() const { return m_options.max_frames > 0 && m_selected >= m_options.max_frames; }

    void request_snapshot(ControlClient& control) {
        if (m_snapshot_id != 0) {
            return; // one is on its way
        }
        m_synced = false;
        m_snapshot_id = control.send(protocol::GetSurfaceParams {});
        m_snapshot_deadline
            = Clock::now() + std::chrono::milliseconds(long(m_options.reply_timeout_s * 1000));
    }

    void on_reply(ControlClient& control) {
        auto reply = control.receive(std::chrono::milliseconds(0));
        if (!reply || reply->id != protocol::RequestId { m_snapshot_id }) {
            return;
        }
        m_snapshot_id = 0;
        if (!reply->ok()) {
            throw Error("get_surface", describe(std::get<protocol::RpcError>(reply->outcome)));
        }
        auto& snapshot
            = std::get<protocol::SurfaceSnapshot>(std::get<protocol::Result>(reply->outcome));
        ++m_summary.snapshots;
        adopt(snapshot, true);
        // Frames that arrived while the snapshot was on its way (Clone pattern).
        std::deque<protocol::SurfaceFrame> pending;
        pending.swap(m_buffer);
        for (protocol::SurfaceFrame& frame : pending) {
            if (frame.header.seq > m_last_seq) {
                on_frame(std::move(frame), control);
            }
        }
    }

    void on_stream(const protocol::Message& message, ControlClient& control) {
        auto decoded = protocol::decode_stream(message);
        if (!decoded) {
            throw Error("stream", "malformed stream message: " + describe(decoded.error()));
        }
        if (auto* frame = std::get_if<protocol::SurfaceFrame>(&decoded.value())) {
            on_frame(std::move(*frame), control);
        }
    }

    void on_frame(protocol::SurfaceFrame frame, ControlClient& control) {
        if (!m_synced) {
            if (m_buffer.size() >= 4096) {
                m_buffer.pop_front();
            }
            m_buffer.push_back(std::move(frame));
            return;
        }
        const std::uint64_t seq = frame.header.seq;
        if (seq <= m_last_seq) {
            return; // older than what we have (e.g. already in the snapshot)
        }
        const bool gap = seq != m_last_seq + 1;
        m_summary.gaps += gap ? 1 : 0;
        const bool fits = frame.header.has_topology
            || (m_topology && frame.header.topology_version == m_topology->version
                && frame.positions.size() == m_vertex_floats);
        if (frame.header.has_topology || (!gap && fits)) {
            adopt(frame, false);
            return;
        }
        // A gap without topology, or positions that do not match: resynchronize.
        m_buffer.push_back(std::move(frame));
        request_snapshot(control);
    }

    /// Makes `frame` the current state and queues it for rendering, unless a frame at least as
    /// new was already queued (a resync snapshot may be older than frames we rendered).
    void adopt(protocol::SurfaceFrame& frame, bool snapshot) {
        if (frame.header.has_topology || snapshot) {
            auto topology = std::make_shared<Topology>();
            topology->version = frame.header.topology_version;
            topology->triangles = std::move(frame.triangles);
            topology->tags = std::move(frame.tags);
            m_topology = std::move(topology);
        }
        m_synced = true;
        m_last_seq = frame.header.seq;
        m_vertex_floats = frame.positions.size();
        if (m_last_emitted && frame.header.seq <= *m_last_emitted) {
            return;
        }
        m_last_emitted = frame.header.seq;
        ++m_summary.received;
        if ((m_summary.received - 1) % m_options.every != 0 || done()) {
            return;
        }
        ++m_selected;
        QueuedFrame queued { frame.header.seq, frame.header.tick, m_topology,
            std::move(frame.positions) };
        {
            std::lock_guard lock(m_queue.mutex);
            if (m_queue.frames.size() >= m_options.max_queue) {
                ++m_summary.dropped;
                --m_selected;
                return;
            }
            m_queue.frames.push_back(std::move(queued));
        }
        m_queue.ready.notify_one();
    }

    const LiveOptions& m_options;
    const ServerInfo& m_server;
    FrameQueue& m_queue;
    const std::atomic<bool>& m_stop;
    const std::atomic<bool>& m_abort;
    LiveSummary& m_summary; ///< receiver-side counters (received, gaps, snapshots, dropped)

    bool m_synced = false;
    std::uint64_t m_last_seq = 0; ///< seq the current state reflects
    std::optional<std::uint64_t> m_last_emitted; ///< newest seq handed to the renderer
    std::size_t m_vertex_floats = 0;
    std::shared_ptr<const Topology> m_topology;
    std::deque<protocol::SurfaceFrame> m_buffer;
    std::int64_t m_snapshot_id = 0;
    Clock::time_point m_snapshot_deadline;
    long m_selected = 0;
};

} // namespace

ServerInfo query_server(const LiveOptions& options) {
    zmq::context_t context(1);
    ControlClient control(context, options.server);
    protocol::HelloParams hello;
    hello.client = "polycut-record";
    hello.protocol = std::string(protocol::kProtocolName);
    const protocol::Result result
        = control.call(hello, std::chrono::milliseconds(long(options.reply_timeout_s * 1000)));
    const auto& info = std::get<protocol::HelloResult>(result);
    ServerInfo server;
    server.stream = options.stream.empty() ? info.stream : options.stream;
    server.rate_hz = info.rate_hz;
    return server;
}

LiveSummary record_live(const LiveOptions& options, const ServerInfo& server,
    FrameRecorder& recorder, const std::atomic<bool>& stop) {
    if (options.every < 1) {
        throw InputError("--every", "must be >= 1");
    }
    LiveSummary summary;
    summary.server_rate_hz = server.rate_hz;
    const Stopwatch wall;
    FrameQueue queue;
    LiveSummary received; // written by the receiver thread only
    std::atomic<bool> abort { false };
    std::thread receiver_thread([&] {
        try {
            Receiver(options, server, queue, stop, abort, received).run();
        } catch (...) {
            std::lock_guard lock(queue.mutex);
            queue.error = std::current_exception();
        }
        {
            std::lock_guard lock(queue.mutex);
            queue.closed = true;
        }
        queue.ready.notify_all();
    });

    std::exception_ptr failure;
    try {
        while (true) {
            QueuedFrame frame;
            {
                std::unique_lock lock(queue.mutex);
                queue.ready.wait(lock, [&] { return !queue.frames.empty() || queue.closed; });
                if (queue.frames.empty()) {
                    break;
                }
                frame = std::move(queue.frames.front());
                queue.frames.pop_front();
            }
            render::SurfaceArrays arrays;
            arrays.positions = frame.positions;
            arrays.triangles = frame.topology->triangles;
            arrays.tags = frame.topology->tags;
            recorder.add(arrays);
            if (summary.rendered == 0) {
                summary.first_seq = frame.seq;
                summary.first_tick = frame.tick;
            }
            ++summary.rendered;
            summary.last_seq = frame.seq;
            summary.last_tick = frame.tick;
        }
    } catch (...) {
        failure = std::current_exception();
    }
    if (failure) {
        abort.store(true);
        receiver_thread.join();
        std::rethrow_exception(failure);
    }
    receiver_thread.join();
    if (queue.error) {
        std::rethrow_exception(queue.error);
    }
    recorder.finish();
    summary.received = received.received;
    summary.gaps = received.gaps;
    summary.snapshots = received.snapshots;
    summary.dropped = received.dropped;
    summary.wall_s = wall.ms() / 1000.0;
    summary.render_ms_mean
        = summary.rendered > 0 ? recorder.busy_ms() / double(summary.rendered) : 0.0;
    return summary;
}

} // namespace polycut::record
