#pragma once
// Supervisor: runs the processes of a host profile (profile.hpp) and keeps them running.
//   - each process in its own process group, stdin /dev/null, stdout+stderr appended to
//     <log_dir>/<name>.txt (a line from the launcher before each start);
//   - a process that ends is restarted by its policy after restartDelay() (0.5 s, 1 s, 2 s ...
//     up to max_delay_s; back to the start after reset_after_s of healthy running);
//   - SIGINT / SIGTERM to the launcher (lcmio/signals.hpp): every process is stopped in the
//     reverse order of the profile (so a logger listed first records to the end): SIGINT to its
//     group, SIGKILL after stop_timeout_s;
//   - a `finish` process that ends (and is not restarted) ends the run: after finish_grace_s the
//     rest is stopped the same way.
// Exit status of run(): 0 stopped by a signal, or the finish process exited 0 (or everything
// ended with 0); 1 the finish process (or, without one, the last process) failed; 124 the
// run's time limit was reached.
#include <chrono>
#include <string>
#include <sys/types.h>
#include <vector>

#include "launch/profile.hpp"

namespace lasonic::launch {

// The executable for command[0]: a path with '/' as it is (if executable); a bare name in each
// of `dirs`, then in $PATH. Empty if not found.
std::string resolveExecutable(const std::string& name, const std::vector<std::string>& dirs);

// Runs `exe` with `args` (argv[0] = exe) to its end, stdin /dev/null, and returns its exit
// status (128 + signal if killed, -1 if it could not be started); its stdout and stderr together
// in `output`. For short checks (lasonic-launch --check), not for the supervised processes.
int runToEnd(const std::string& exe, const std::vector<std::string>& args, std::string& output);

class Supervisor {
 public:
  Supervisor(HostProfile profile, std::string log_dir, std::vector<std::string> search_dirs);

  // Resolves every enabled process's executable. Returns false (after printing which and where
  // it looked) if a non-optional one is missing; optional ones are reported and left out.
  bool prepare(bool create_log_dir = true);
  // max_time_s > 0: stop everything after that long and return 124 (a bound for demos and tests).
  int run(double max_time_s = 0);

 private:
  using Clock = std::chrono::steady_clock;
  struct Proc {
    ProcessSpec spec;
    std::string exe;
    bool skip = false;
    pid_t pid = 0;
    int starts = 0;
    int consecutive = 0;  // restarts since the last healthy run
    bool done = false;    // ended and not to be restarted
    int last_status = 0;  // 0 ok, else exit code or 128 + signal
    Clock::time_point started, next_start;
  };
  void start(Proc& p);
  void reap(Clock::time_point now);
  void stopAll();
  bool stopOne(Proc& p, int sig, double timeout_s);
  Proc* byPid(pid_t pid);

  HostProfile profile_;
  std::string log_dir_;
  std::vector<std::string> search_dirs_;
  std::vector<Proc> procs_;
  Clock::time_point t0_;
  bool finishing_ = false;
  Clock::time_point finish_at_;
  int exit_code_ = 0;
  bool bad_config_ = false;  // a process exited 2: not restarted, and the launcher exits 2 at the end
};

}  // namespace lasonic::launch
