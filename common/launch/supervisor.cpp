#include "launch/supervisor.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <sstream>
#include <thread>

#include "lcmio/signals.hpp"

namespace lasonic::launch {
namespace {

// As the processes' own log lines (core/logging.cpp): local date and time with microseconds, so
// the launcher's lines and theirs interleave in one order and line up with an LCM log's times.
std::string stamp() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t t = std::chrono::system_clock::to_time_t(now);
  const auto us = std::chrono::duration_cast<std::chrono::microseconds>(now.time_since_epoch()).count() % 1000000;
  std::tm tm{};
  localtime_r(&t, &tm);
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%04d-%02d-%02d %02d:%02d:%02d.%06d", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday,
                tm.tm_hour, tm.tm_min, tm.tm_sec, static_cast<int>(us));
  return buf;
}

template <typename... A>
void say(const char* fmt, A... args) {
  std::fprintf(stderr, "[lasonic-launch %s] ", stamp().c_str());
  std::fprintf(stderr, fmt, args...);
  std::fputc('\n', stderr);
  std::fflush(stderr);
}

bool executable(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(path.c_str(), X_OK) == 0;
}

std::string describeStatus(int status) {
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "exited normally";
  if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return std::string("killed by signal ") + std::to_string(WTERMSIG(status)) + " (" +
                                  strsignal(WTERMSIG(status)) + ")";
  return "ended";
}

double seconds(std::chrono::steady_clock::duration d) { return std::chrono::duration<double>(d).count(); }

}  // namespace

std::string resolveExecutable(const std::string& name, const std::vector<std::string>& dirs) {
  if (name.find('/') != std::string::npos) return executable(name) ? name : std::string{};
  std::vector<std::string> all = dirs;
  if (const char* path = std::getenv("PATH")) {
    std::stringstream ss(path);
    std::string d;
    while (std::getline(ss, d, ':'))
      if (!d.empty()) all.push_back(d);
  }
  for (const std::string& d : all) {
    const std::string p = d + "/" + name;
    if (executable(p)) return p;
  }
  return {};
}

int runToEnd(const std::string& exe, const std::vector<std::string>& args, std::string& output) {
  output.clear();
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return -1;
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(exe.c_str()));
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return -1;
  }
  if (pid == 0) {
    const int devnull = ::open("/dev/null", O_RDONLY);
    if (devnull >= 0) ::dup2(devnull, 0);
    ::dup2(fds[1], 1);
    ::dup2(fds[1], 2);
    ::execv(exe.c_str(), argv.data());
    ::_exit(127);
  }
  ::close(fds[1]);
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(fds[0], buf, sizeof(buf));
    if (n > 0) output.append(buf, static_cast<size_t>(n));
    else if (n == 0 || errno != EINTR) break;
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1;
}

Supervisor::Supervisor(HostProfile profile, std::string log_dir, std::vector<std::string> search_dirs)
    : profile_(std::move(profile)), log_dir_(std::move(log_dir)), search_dirs_(std::move(search_dirs)) {
  for (const ProcessSpec& s : profile_.processes) {
    Proc p;
    p.spec = s;
    procs_.push_back(std::move(p));
  }
}

bool Supervisor::prepare(bool create_log_dir) {
  bool ok = true;
  std::string where;
  for (const std::string& d : search_dirs_) where += d + ", ";
  where += "$PATH";
  for (Proc& p : procs_) {
    if (!p.spec.enabled) {
      p.skip = true;
      continue;
    }
    p.exe = resolveExecutable(p.spec.command[0], search_dirs_);
    if (!p.exe.empty()) continue;
    p.skip = true;
    if (p.spec.optional) {
      say("%s: executable '%s' not found (looked in %s): optional, not started", p.spec.name.c_str(),
          p.spec.command[0].c_str(), where.c_str());
    } else {
      say("error: %s: executable '%s' not found (looked in %s); build it, or mark it optional: true in the "
          "profile",
          p.spec.name.c_str(), p.spec.command[0].c_str(), where.c_str());
      ok = false;
    }
  }
  if (!create_log_dir) return ok;
  std::error_code ec;
  std::filesystem::create_directories(log_dir_, ec);
  if (ec) {
    say("error: cannot create the log directory %s: %s", log_dir_.c_str(), ec.message().c_str());
    ok = false;
  }
  return ok;
}

void Supervisor::start(Proc& p) {
  const std::string log = log_dir_ + "/" + p.spec.name + ".txt";
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) {
    say("error: %s: cannot open %s: %s; not started", p.spec.name.c_str(), log.c_str(), std::strerror(errno));
    p.done = true;
    p.last_status = 1;
    return;
  }
  std::string line = "[lasonic-launch " + stamp() + "] start " + std::to_string(p.starts + 1) + ":";
  for (const std::string& a : p.spec.command) line += " " + a;
  line += "\n";
  if (::write(fd, line.data(), line.size()) < 0) { /* the log is best effort */ }

  std::vector<char*> argv;
  for (const std::string& a : p.spec.command) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);
    struct sigaction dfl {};
    dfl.sa_handler = SIG_DFL;
    for (int sig : {SIGINT, SIGTERM, SIGQUIT, SIGPIPE, SIGCHLD, SIGHUP}) ::sigaction(sig, &dfl, nullptr);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    const int devnull = ::open("/dev/null", O_RDONLY);
    if (devnull >= 0) ::dup2(devnull, 0);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    ::execv(p.exe.c_str(), argv.data());
    const std::string err = "[lasonic-launch] exec " + p.exe + " failed: " + std::strerror(errno) + "\n";
    if (::write(2, err.data(), err.size()) < 0) { /* nothing left to do */ }
    ::_exit(127);
  }
  ::close(fd);
  if (pid < 0) {
    say("error: %s: fork failed: %s", p.spec.name.c_str(), std::strerror(errno));
    p.next_start = Clock::now() + std::chrono::milliseconds(static_cast<int64_t>(1000 * profile_.backoff.max_delay_s));
    return;
  }
  ::setpgid(pid, pid);  // also here: no race with a signal sent right after
  p.pid = pid;
  ++p.starts;
  p.started = Clock::now();
  say("%s started (pid %d)%s", p.spec.name.c_str(), static_cast<int>(pid),
      p.starts > 1 ? (" (restart " + std::to_string(p.starts - 1) + ")").c_str() : "");
}

Supervisor::Proc* Supervisor::byPid(pid_t pid) {
  for (Proc& p : procs_)
    if (p.pid == pid) return &p;
  return nullptr;
}

void Supervisor::reap(Clock::time_point now) {
  int status = 0;
  pid_t pid;
  while ((pid = ::waitpid(-1, &status, WNOHANG)) > 0) {
    Proc* p = byPid(pid);
    if (!p) continue;
    p->pid = 0;
    const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    p->last_status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    const double up = seconds(now - p->started);
    // Exit 2 is a bad command line or configuration (README "Processes: start-up, exit codes,
    // status"): starting it again cannot help, and the systemd units do not either.
    const bool bad_config = WIFEXITED(status) && WEXITSTATUS(status) == 2;
    if (bad_config) bad_config_ = true;
    const bool again = !finishing_ && !bad_config &&
                       (p->spec.restart == RestartPolicy::Always || (p->spec.restart == RestartPolicy::OnFailure && !ok));
    if (!again) {
      p->done = true;
      if (bad_config)
        say("%s exited 2 (bad command line or configuration: see %s/%s.txt) after %.1f s: not restarted",
            p->spec.name.c_str(), log_dir_.c_str(), p->spec.name.c_str(), up);
      else
        say("%s %s after %.1f s", p->spec.name.c_str(), describeStatus(status).c_str(), up);
      if (p->spec.finish && !finishing_) {
        finishing_ = true;
        finish_at_ = now + std::chrono::milliseconds(static_cast<int64_t>(1000 * profile_.finish_grace_s));
        exit_code_ = ok ? 0 : 1;
        say("%s has finished: stopping the others in %.1f s", p->spec.name.c_str(), profile_.finish_grace_s);
      }
      continue;
    }
    p->consecutive = up >= profile_.backoff.reset_after_s ? 1 : p->consecutive + 1;
    const double delay = restartDelay(profile_.backoff, p->consecutive);
    p->next_start = now + std::chrono::milliseconds(static_cast<int64_t>(1000 * delay));
    say("%s %s after %.1f s; restarting in %.1f s", p->spec.name.c_str(), describeStatus(status).c_str(), up, delay);
  }
}

bool Supervisor::stopOne(Proc& p, int sig, double timeout_s) {
  if (p.pid <= 0) return true;
  ::kill(-p.pid, sig);
  const auto until = Clock::now() + std::chrono::milliseconds(static_cast<int64_t>(1000 * timeout_s));
  while (Clock::now() < until) {
    int status = 0;
    const pid_t r = ::waitpid(p.pid, &status, WNOHANG);
    if (r == p.pid) {
      const bool clean = (WIFEXITED(status) && (WEXITSTATUS(status) == 0 || WEXITSTATUS(status) == 130)) ||
                         (WIFSIGNALED(status) && (WTERMSIG(status) == SIGINT || WTERMSIG(status) == SIGTERM));
      if (clean) say("%s stopped", p.spec.name.c_str());
      else say("%s %s on stopping", p.spec.name.c_str(), describeStatus(status).c_str());
      p.pid = 0;
      p.done = true;
      return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

void Supervisor::stopAll() {
  for (auto it = procs_.rbegin(); it != procs_.rend(); ++it) {
    Proc& p = *it;
    p.done = true;
    if (p.pid <= 0) continue;
    if (!stopOne(p, SIGINT, profile_.stop_timeout_s)) {
      say("%s (pid %d) ignored SIGINT for %.1f s: killing it", p.spec.name.c_str(), static_cast<int>(p.pid),
          profile_.stop_timeout_s);
      stopOne(p, SIGKILL, 5.0);
    }
  }
}

int Supervisor::run(double max_time_s) {
  shutdown::installHandlers();
  t0_ = Clock::now();
  const auto deadline = t0_ + std::chrono::milliseconds(static_cast<int64_t>(1000 * max_time_s));
  for (Proc& p : procs_) {
    p.next_start = t0_ + std::chrono::milliseconds(static_cast<int64_t>(1000 * p.spec.start_delay_s));
    if (p.skip) p.done = true;
  }
  size_t to_run = 0;
  for (const Proc& p : procs_) to_run += p.skip ? 0 : 1;
  say("host %s: %zu of %zu processes, LCM %s, logs in %s/", profile_.host.c_str(), to_run, procs_.size(),
      profile_.lcm_url.c_str(), log_dir_.c_str());
  while (true) {
    const auto now = Clock::now();
    reap(now);
    if (shutdown::requested()) {
      say("signal received: stopping every process");
      stopAll();
      return bad_config_ ? 2 : 0;
    }
    if (max_time_s > 0 && now >= deadline) {
      say("still running after --max-time %.0f s: stopping every process", max_time_s);
      stopAll();
      return 124;
    }
    if (finishing_ && now >= finish_at_) {
      stopAll();
      return bad_config_ ? 2 : exit_code_;
    }
    bool alive = false;
    for (Proc& p : procs_) {
      if (p.done) continue;
      alive = true;
      if (p.pid == 0 && !finishing_ && now >= p.next_start) start(p);
    }
    if (!alive && !finishing_) {
      int worst = 0;
      for (const Proc& p : procs_)
        if (!p.skip && p.last_status != 0) worst = 1;
      say("every process has ended");
      return bad_config_ ? 2 : worst;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

}  // namespace lasonic::launch
