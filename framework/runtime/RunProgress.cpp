#include "framework/runtime/RunProgress.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "framework/runtime/Scheduler.h"

namespace trephine {

namespace {
std::string seconds(double s) {
  std::ostringstream text;
  text.setf(std::ios::fixed);
  text.precision(s < 10 ? 1 : 0);
  text << s << " s";
  return text.str();
}
}  // namespace

RunProgress::RunProgress(const Scheduler& scheduler, double plannedS, std::ostream& out, double intervalS,
                         bool terminal)
    : m_scheduler(scheduler), m_planned(plannedS), m_out(out), m_interval(intervalS), m_terminal(terminal) {
  m_thread = std::thread([this] { report(); });
}

RunProgress::~RunProgress() {
  {
    std::lock_guard lock(m_mutex);
    m_stopping = true;
  }
  m_wake.notify_all();
  m_thread.join();
  if (m_terminal && m_reported) m_out << "\r\033[K" << std::flush;  // the summary takes the line
}

std::string RunProgress::describe(double simulatedS, double plannedS, double wallS) {
  std::string line =
      "progress  " + seconds(simulatedS) + " of " + seconds(plannedS) + " simulated, " + seconds(wallS) + " wall";
  if (simulatedS > 0 && plannedS > simulatedS) {
    const double left = wallS * (plannedS - simulatedS) / simulatedS;
    line += ", about " + seconds(std::ceil(left)) + " left";
  }
  return line;
}

void RunProgress::report() {
  const auto start = std::chrono::steady_clock::now();
  std::unique_lock lock(m_mutex);
  while (!m_wake.wait_for(lock, std::chrono::duration<double>(m_interval), [this] { return m_stopping; })) {
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::string line = describe(m_scheduler.progress(), m_planned, wall);
    if (m_terminal) {
      m_out << "\r\033[K" << line << std::flush;
    } else {
      m_out << line << "\n" << std::flush;
    }
    m_reported = true;
  }
}

}  // namespace trephine
