#include "launch/profile.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <set>

namespace lasonic::launch {

std::string expand(const std::string& text, const std::map<std::string, std::string>& vars,
                   const std::function<void(const std::string&)>& unknown) {
  std::string out;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '$' || i + 1 >= text.size()) {
      out += text[i];
      continue;
    }
    if (text[i + 1] == '$') {
      out += '$';
      ++i;
      continue;
    }
    if (text[i + 1] != '{') {
      out += text[i];
      continue;
    }
    const size_t end = text.find('}', i + 2);
    if (end == std::string::npos) {
      unknown(text.substr(i));
      return out;
    }
    const std::string name = text.substr(i + 2, end - i - 2);
    const auto it = vars.find(name);
    if (it == vars.end()) {
      unknown(name);
    } else {
      out += it->second;
    }
    i = end;
  }
  return out;
}

std::vector<std::pair<std::string, std::string>> filesNamed(const ProcessSpec& spec) {
  std::vector<std::pair<std::string, std::string>> out;
  const auto& cmd = spec.command;
  for (size_t i = 1; i < cmd.size(); ++i)
    for (const std::string opt : {"--config", "--scenario"}) {
      if (cmd[i] == opt && i + 1 < cmd.size()) out.emplace_back(opt, cmd[i + 1]);
      else if (cmd[i].rfind(opt + "=", 0) == 0) out.emplace_back(opt, cmd[i].substr(opt.size() + 1));
    }
  return out;
}

double restartDelay(const BackoffParams& p, int consecutive) {
  const int n = std::max(1, consecutive);
  return std::min(p.max_delay_s, p.initial_delay_s * std::pow(2.0, std::min(n - 1, 30)));
}

HostProfile loadProfile(const Config& root, const std::map<std::string, std::string>& overrides,
                        const std::map<std::string, std::string>& builtins) {
  root.allowOnly({"host", "lcm_url", "vars", "restart", "stop_timeout_s", "finish_grace_s", "processes"});
  HostProfile p;
  p.host = root.get<std::string>("host", "localhost");

  // Variables: builtins < environment (only names used) < vars < --set.
  std::map<std::string, std::string> vars = builtins;
  const Config vs = root.section("vars");
  for (const std::string& k : vs.keys()) vars[k] = vs.get<std::string>(k, "");
  for (const auto& [k, v] : overrides) vars[k] = v;
  auto lookup = [&](const Config& where, const std::string& key, const std::string& text) {
    return expand(text, vars, [&](const std::string& name) {
      if (const char* env = std::getenv(name.c_str())) {
        vars[name] = env;
        return;
      }
      where.fail(key, "unknown variable ${" + name + "} (define it under vars:, with --set " + name +
                          "=VALUE, or in the environment)");
    });
  };
  // The variables the profile uses, so that a --set of one it does not use is an error (a
  // misspelt name, or a variable of another profile, would otherwise change nothing).
  std::set<std::string> used;
  const auto noteUsed = [&used](const std::string& text) {
    for (size_t i = text.find("${"); i != std::string::npos; i = text.find("${", i + 2)) {
      // As expand() reads it: "$$" is a literal "$", so "${" starts a variable after an even
      // number of "$" ("$${x}" is a literal, "$$${x}" a "$" and then ${x}).
      size_t run = 1;
      while (run <= i && text[i - run] == '$') ++run;
      if (run % 2 == 0) continue;
      const size_t end = text.find('}', i + 2);
      if (end == std::string::npos) break;
      used.insert(text.substr(i + 2, end - i - 2));
    }
  };
  // Expanding twice lets an environment variable found on the first pass be substituted.
  auto expandValue = [&](const Config& where, const std::string& key, const std::string& text) {
    noteUsed(text);
    (void)lookup(where, key, text);
    return lookup(where, key, text);
  };
  if (root.has("lcm_url")) {
    vars["lcm_url"] = expandValue(root, "lcm_url", root.get<std::string>("lcm_url", ""));
  }
  if (overrides.count("lcm_url")) vars["lcm_url"] = overrides.at("lcm_url");
  if (!vars.count("lcm_url")) root.fail("lcm_url", "is required (the LCM URL every process of the host uses)");
  p.lcm_url = vars["lcm_url"];
  // Every process would be started with `--lcm-url ""` and fail (or take LCM's default).
  if (p.lcm_url.empty()) {
    if (overrides.count("lcm_url")) throw ConfigError("--lcm-url (or --set lcm_url): must not be empty");
    root.fail("lcm_url", "must not be empty (the LCM URL every process of the host uses)");
  }

  const Config r = root.section("restart");
  r.allowOnly({"initial_delay_s", "max_delay_s", "reset_after_s"});
  // Times at most kMaxSeconds (profile.hpp).
  const Range positive{0, kMaxSeconds, true}, non_negative = Range::between(0, kMaxSeconds);
  p.backoff.initial_delay_s = r.get("initial_delay_s", p.backoff.initial_delay_s, positive);
  p.backoff.max_delay_s = r.get("max_delay_s", p.backoff.max_delay_s, positive);
  p.backoff.reset_after_s = r.get("reset_after_s", p.backoff.reset_after_s, non_negative);
  if (p.backoff.max_delay_s < p.backoff.initial_delay_s) r.fail("max_delay_s", "must be >= initial_delay_s");
  p.stop_timeout_s = root.get("stop_timeout_s", p.stop_timeout_s, positive);
  p.finish_grace_s = root.get("finish_grace_s", p.finish_grace_s, non_negative);

  const std::vector<Config> procs = root.list("processes");
  if (procs.empty()) root.fail("processes", "must list at least one process");
  std::set<std::string> names;
  for (const Config& c : procs) {
    c.allowOnly({"name", "command", "restart", "start_delay_s", "optional", "finish", "enabled"});
    ProcessSpec s;
    s.name = c.require<std::string>("name");
    if (s.name.empty() || s.name.find('/') != std::string::npos || s.name[0] == '.')
      c.fail("name", "must be a plain file name (it names the log file)");
    if (!names.insert(s.name).second) c.fail("name", "\"" + s.name + "\" is used twice");
    if (!c.has("command") || !c.node()["command"].IsSequence() || c.node()["command"].size() == 0)
      c.fail("command", "must be a non-empty list: [executable, arguments...]");
    for (size_t i = 0; i < c.node()["command"].size(); ++i) {
      const std::string key = "command[" + std::to_string(i) + "]";
      std::string arg;
      try {
        arg = c.node()["command"][i].as<std::string>();
      } catch (const YAML::Exception&) {
        c.fail(key, "must be a string");
      }
      s.command.push_back(expandValue(c, key, arg));
    }
    s.restart = c.getChoice("restart", s.restart,
                            {{"always", RestartPolicy::Always}, {"on-failure", RestartPolicy::OnFailure},
                             {"never", RestartPolicy::Never}});
    s.start_delay_s = c.get("start_delay_s", s.start_delay_s, non_negative);
    s.optional = c.get<bool>("optional", false);
    s.finish = c.get<bool>("finish", false);
    if (c.has("enabled")) {
      const std::string e = expandValue(c, "enabled", c.get<std::string>("enabled", "true"));
      if (e == "true" || e == "1" || e == "yes") s.enabled = true;
      else if (e == "false" || e == "0" || e == "no" || e.empty()) s.enabled = false;
      else c.fail("enabled", "must be true or false (got \"" + e + "\")");
    }
    p.processes.push_back(std::move(s));
  }
  for (const auto& [k, v] : overrides)
    if (k != "lcm_url" && !used.count(k)) {
      std::string list;
      for (const std::string& u : used) list += (list.empty() ? "" : ", ") + u;
      throw ConfigError("--set " + k + ": the profile uses no variable ${" + k + "}" +
                        (list.empty() ? std::string(" (it uses none)") : " (it uses: " + list + ")"));
    }
  return p;
}

}  // namespace lasonic::launch
