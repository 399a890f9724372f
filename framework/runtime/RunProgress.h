#pragma once
// What a long run has done so far, told while it goes on: the simulated time
// out of the planned, the wall time, and the time left at the pace so far.
// A thread of its own reads the scheduler's progress (an atomic) every
// `interval`; the run's threads never wait on it. On a terminal the line is
// rewritten in place; elsewhere (a log, CI) each report is a line of its own.
// Nothing is said of a run that ends before the first report is due.
#include <condition_variable>
#include <mutex>
#include <ostream>
#include <string>
#include <thread>

namespace trephine {

class Scheduler;

class RunProgress {
 public:
  RunProgress(const Scheduler& scheduler, double plannedS, std::ostream& out, double intervalS, bool terminal);
  // Stops reporting (and clears a terminal's line).
  ~RunProgress();
  RunProgress(const RunProgress&) = delete;
  RunProgress& operator=(const RunProgress&) = delete;

  // "progress  4.0 of 18.0 s simulated, 2.1 s wall, about 7 s left".
  static std::string describe(double simulatedS, double plannedS, double wallS);

 private:
  void report();

  const Scheduler& m_scheduler;
  const double m_planned;  // s, simulated
  std::ostream& m_out;
  const double m_interval;  // s, wall
  const bool m_terminal;
  bool m_reported = false;  // a line is on the terminal
  bool m_stopping = false;
  std::mutex m_mutex;
  std::condition_variable m_wake;
  std::thread m_thread;
};

}  // namespace trephine
