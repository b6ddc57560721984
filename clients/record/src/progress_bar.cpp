// Progress bar on stderr (see progress_bar.hpp).
#include "progress_bar.hpp"

#include <algorithm>
#include <array>
#include <unistd.h>

namespace polycut::record {

ProgressBar::ProgressBar(
    long total, std::string label, std::string unit, bool enabled, std::FILE* out)
    : m_total(std::max(total, 1L))
    , m_label(std::move(label))
    , m_unit(std::move(unit))
    , m_enabled(enabled)
    , m_out(out)
    , m_tty(::isatty(::fileno(out)) != 0)
    , m_start(std::chrono::steady_clock::now())
    , m_last_draw(m_start) { }

std::string ProgressBar::line(
    const std::string& label, const std::string& unit, long done, long total, double elapsed_s) {
    constexpr int kWidth = 28;
    total = std::max(total, 1L);
    const double fraction = std::clamp(double(done) / double(total), 0.0, 1.0);
    const int filled = static_cast<int>(fraction * kWidth + 1e-9);
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.append(static_cast<std::size_t>(kWidth - filled), '.');
    const double rate = elapsed_s > 0 ? double(done) / elapsed_s : 0.0;
    std::array<char, 256> text {};
    if (rate > 0 && done < total) {
        std::snprintf(text.data(), text.size(), "%s [%s] %3d%% %ld/%ld %s  %.1f/s  ETA %.0f s",
            label.c_str(), bar.c_str(), static_cast<int>(fraction * 100), done, total, unit.c_str(),
            rate, double(total - done) / rate);
    } else {
        std::snprintf(text.data(), text.size(), "%s [%s] %3d%% %ld/%ld %s  %.1f/s", label.c_str(),
            bar.c_str(), static_cast<int>(fraction * 100), done, total, unit.c_str(), rate);
    }
    return text.data();
}

void ProgressBar::update(long done) {
    m_done = done;
    if (!m_enabled) {
        return;
    }
    const auto now = std::chrono::steady_clock::now();
    if (m_tty) {
        if (now - m_last_draw >= std::chrono::milliseconds(100)) {
            m_last_draw = now;
            draw(false);
        }
        return;
    }
    const int decile = static_cast<int>(10 * std::min(done, m_total) / m_total);
    if (decile != m_last_decile) {
        m_last_decile = decile;
        draw(false);
    }
}

void ProgressBar::finish() {
    // Off a terminal the 100 % line may already be out.
    if (m_enabled && (m_tty || m_last_decile != 10 || m_done < m_total)) {
        draw(true);
    }
}

void ProgressBar::draw(bool final) {
    const double elapsed
        = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    const std::string text = line(m_label, m_unit, m_done, m_total, elapsed);
    if (m_tty) {
        std::fprintf(m_out, "\r%s\033[K%s", text.c_str(), final ? "\n" : "");
    } else {
        std::fprintf(m_out, "%s\n", text.c_str());
    }
    std::fflush(m_out);
}

} // namespace polycut::record
