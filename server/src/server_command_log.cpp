// Command log writer and replay (see server_command_log.hpp).
#include "server_command_log.hpp"

#include "polycut/common/error.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>

namespace polycut::server {

using json = nlohmann::json;

std::string client_hex(std::string_view identity) {
    static constexpr char kDigits[] = "0123456789abcdef";
    std::string out;
    out.reserve(identity.size() * 2);
    for (const char c : identity) {
        const auto byte = static_cast<unsigned char>(c);
        out += kDigits[byte >> 4];
        out += kDigits[byte & 15];
    }
    return out.empty() ? std::string("-") : out;
}

CommandLog::CommandLog(const std::string& path, const std::optional<std::string>& scene_file,
    const std::string& scene_dir)
    : m_out(path, std::ios::binary | std::ios::trunc) {
    if (!m_out) {
        throw FileError(path, 0, "cannot create the command log");
    }
    json header = { { "polycut_command_log", 1 }, { "scene_dir", scene_dir } };
    header["scene_file"] = scene_file ? json(*scene_file) : json(nullptr);
    m_out << header.dump() << '\n' << std::flush;
}

void CommandLog::record(
    std::int64_t tick, std::string_view client, const protocol::Request& request) {
    const protocol::Message encoded
        = protocol::encode_request(request, protocol::EncodeOptions { false });
    // The request text is already compact JSON; splice it in rather than re-parse it.
    m_out << "{\"tick\":" << tick << ",\"client\":\"" << client_hex(client)
          << "\",\"request\":" << encoded.front() << "}\n"
          << std::flush;
}

void CommandLog::end(std::int64_t tick) {
    m_out << "{\"tick\":" << tick << ",\"end\":true}\n" << std::flush;
}

namespace {

std::string hex_to_bytes(const std::string& hex) {
    if (hex == "-") {
        return {};
    }
    std::string out;
    for (std::size_t i = 0; i + 1 < hex.size(); i += 2) {
        out += static_cast<char>(std::stoi(hex.substr(i, 2), nullptr, 16));
    }
    return out;
}

} // namespace

ReplaySummary replay_command_log(const std::string& path, Session& session,
    const ReplayTickCallback& on_tick, std::optional<std::int64_t> until_tick) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw FileError(path, 0, "cannot open the command log");
    }
    ReplaySummary summary;
    auto step_to = [&](std::int64_t tick) {
        if (until_tick) {
            tick = std::min(tick, *until_tick);
        }
        while (session.tick() < tick) {
            const sim::StepReport report = session.step();
            summary.sweeps_rejected += session.take_rejections().size();
            if (on_tick) {
                on_tick(session, report);
            }
        }
    };
    std::string line;
    long line_no = 0;
    bool stopped = false;
    while (!stopped && std::getline(in, line)) {
        ++line_no;
        if (line.empty()) {
            continue;
        }
        json record;
        try {
            record = json::parse(line);
        } catch (const json::exception& e) {
            throw FileError(path, line_no, std::string("not JSON: ") + e.what());
        }
        if (!record.is_object()) {
            throw FileError(path, line_no, "a log line must be a JSON object");
        }
        if (line_no == 1) {
            if (!record.contains("polycut_command_log")) {
                throw FileError(path, line_no, "not a polycut command log (no header)");
            }
            const json& file = record.value("scene_file", json(nullptr));
            if (file.is_string()) {
                session.load_scene_file(file.get<std::string>());
            }
            continue;
        }
        if (!record.contains("tick") || !record["tick"].is_number_integer()) {
            throw FileError(path, line_no, "missing integer \"tick\"");
        }
        const std::int64_t tick = record["tick"].get<std::int64_t>();
        if (tick < session.tick()) {
            throw FileError(path, line_no,
                "tick " + std::to_string(tick) + " is before the session's tick "
                    + std::to_string(session.tick()));
        }
        step_to(tick);
        if (until_tick && session.tick() >= *until_tick && tick > *until_tick) {
            stopped = true;
            break;
        }
        if (record.value("end", false)) {
            stopped = true;
            break;
        }
        if (!record.contains("request") || !record["request"].is_object()) {
            throw FileError(path, line_no, "missing \"request\" object");
        }
        const std::string text = record["request"].dump();
        const std::string_view frame(text);
        // The server accepted this request within its limits; the log holds it as one JSON
        // frame (a cut's binary triangles written out as numbers, ~2.7x the bytes), so the
        // wire's frame limits do not apply here (a 2,000-triangle cut is ~390 kB of JSON).
        protocol::Limits limits;
        limits.max_json_bytes = limits.max_frame_bytes
            = std::max<std::uint64_t>(limits.max_frame_bytes, std::uint64_t(text.size()));
        auto request
            = protocol::decode_request(std::span<const std::string_view>(&frame, 1), limits);
        if (!request) {
            throw FileError(path, line_no, "invalid request: " + request.error().error.reason);
        }
        const std::string client = hex_to_bytes(record.value("client", std::string("-")));
        const ApplyOutcome outcome
            = session.apply(request->params, client, 0.0, request->id.has_value());
        summary.sweeps_rejected += session.take_rejections().size();
        ++summary.commands;
        summary.rejected += outcome.ok() ? 0 : 1;
    }
    if (until_tick && !stopped) {
        step_to(*until_tick);
    }
    summary.tick = session.tick();
    summary.state_hash = session.state_hash();
    summary.topology_version = session.topology_version();
    summary.scene = session.scene_name();
    return summary;
}

} // namespace polycut::server
