// lasonic-replay --in LOG --out LOG [--config FILE]... [--stages LIST]
//
// Runs the pipeline stages (complement, pilot, navigator) in one process over a log's raw channels, deterministically: every
// stage has its own Node on an in-process bus (LocalBus: LCM's memq:// delivery order); each
// input event is published into it and the queue drained before the next, so the stages see
// exactly the log's order. A recorder on ".*" writes every message it sees (inputs and outputs)
// to the output log; an output event carries the timestamp of the input event that caused it.
// Channels that the stages produce are dropped from the input (they are recomputed), as is
// PROCESS_STATUS.
//
// --threads spreads the stages over threads (StagePipeline: each thread its own bus, with the
// one bus's delivery order kept exactly), and the log is written by a thread of its own
// (LogWriter); the output is the same, byte for byte, with any number of threads.
//
// --stages runs only some of the stages (comma-separated; default all three); only their
// outputs are dropped from the input, so the others' outputs in the log are inputs. E.g.
// `--stages navigator` on a log recorded on the navigator's host recomputes what the live
// navigator published from what it received there (README "Deploying on two computers").
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "core/cli.hpp"
#include "core/same_file.hpp"
#include "core/config.hpp"
#include "core/logging.hpp"
#include "lcmio/eventlog.hpp"
#include "lcmio/node.hpp"
#include "lcmio/replay_meter.hpp"
#include "lcmio/stage_pipeline.hpp"
#include "stages/complement_stage.hpp"
#include "stages/navigator_stage.hpp"
#include "stages/pilot_stage.hpp"

namespace {

using namespace lasonic;

// The stages in pipeline order, each with the channels it publishes (recomputed: never taken
// from the input log when the stage runs).
struct StageInfo {
  const char* name;
  std::vector<std::string> outputs;
};
const std::vector<StageInfo> kStages = {
    {"complement", {channels::RADAR_MAP, channels::SONAR_HYPOTHESIS, channels::SONAR_COMPLEMENT}},
    {"pilot", {channels::AGM_OPERATIONAL, channels::SECTOR_MAP}},
    {"navigator", {channels::AGM_TACTICAL, channels::AGM_LINES, channels::CURRENT_SENSOR_MAP}},
};

struct Recorder {
  LogWriter* out = nullptr;
  int64_t timestamp = 0;  // of the input event being processed
  void handleMessage(const std::string& channel, LocalBus::Bytes&& data) {
    out->writeOwned(channel, timestamp, std::move(data));
  }
};

// The thread of each stage: the chain complement -> navigator -> pilot (the pilot reads the
// navigator's AGM_TACTICAL, so it runs on the navigator's thread or a later one; StagePipeline
// checks it), the stages that run spread over at most `threads` threads. With fewer threads than
// stages the first ones share a thread and the pilot keeps one to itself (with two threads the
// complement and the navigator share: since scan matching the navigator is as much work as the
// pilot, so three threads are faster even on two cores, README "Recording and replaying").
std::map<std::string, int> stageThreads(const std::set<std::string>& stages, int threads) {
  std::vector<std::string> chain;
  for (const char* s : {"complement", "navigator", "pilot"})
    if (stages.count(s)) chain.push_back(s);
  std::map<std::string, int> out;
  const int n = std::max(1, std::min(threads, static_cast<int>(chain.size())));
  const int skip = static_cast<int>(chain.size()) - n;  // stages that share the first thread, beyond one
  for (size_t i = 0; i < chain.size(); ++i) out[chain[i]] = std::max(0, static_cast<int>(i) - skip);
  return out;
}

int replay(const std::string& in_path, const std::string& out_path, const Config& root,
           const std::set<std::string>& stages, int threads, bool print_status) {
  const std::map<std::string, int> thread_of = stageThreads(stages, threads);
  int nthreads = 1;
  for (const auto& [name, t] : thread_of) nthreads = std::max(nthreads, t + 1);
  StagePipeline pipeline(nthreads);
  const Node::Options offline{/*heartbeat=*/false, /*install_signal_handlers=*/false};

  // ---- the stages, in pipeline order (the order of subscribing on one bus). Add a stage here
  // (and to kStages, stageThreads): its Node and its object. Every configuration is read, so that
  // a bad one fails the same whether its stage runs or not.
  const ComplementConfig complement_cfg = complementConfig(root.section("complement"));
  const PilotConfig pilot_cfg = pilotConfigFromRoot(root);
  const NavigatorConfig navigator_cfg = navigatorConfigFromRoot(root);
  std::vector<std::unique_ptr<Node>> nodes;
  std::optional<ComplementStage> complement_stage;
  std::optional<PilotStage> pilot_stage;
  std::optional<NavigatorStage> navigator_stage;
  const auto make = [&](const char* stage, const char* process, auto& object, const auto& cfg) {
    if (!stages.count(stage)) return;
    const int t = thread_of.at(stage);
    pipeline.beginStage(t);
    nodes.push_back(std::make_unique<Node>(process, pipeline.bus(t), offline));
    object.emplace(*nodes.back(), cfg);
    pipeline.endStage();
  };
  make("complement", "lasonic-complement", complement_stage, complement_cfg);
  make("pilot", "lasonic-pilot", pilot_stage, pilot_cfg);
  make("navigator", "lasonic-navigator", navigator_stage, navigator_cfg);
  // Both stages read each LASER_SCAN and place its readings with their own (equal) odometry
  // history: once is enough when they run on one thread (complement/shared_placement.hpp: used
  // only when the message, the scan and the history are equal).
  const auto placement = std::make_shared<complement::SharedPlacement>();
  if (complement_stage && pilot_stage && thread_of.at("complement") == thread_of.at("pilot")) {
    complement_stage->sharePlacement(placement);
    pilot_stage->sharePlacement(placement);
  }
  // ----
  std::set<std::string, std::less<>> derived = {channels::PROCESS_STATUS};
  for (const StageInfo& s : kStages)
    if (stages.count(s.name)) derived.insert(s.outputs.begin(), s.outputs.end());

  // Every message on the last thread's bus, after its subscriptions (as a ".*" subscription
  // made last), its buffer taken over: large ones are written in place and come back to the bus.
  LogWriter out(out_path);
  Recorder recorder{&out};
  const std::shared_ptr<LocalBus>& last_bus = pipeline.bus(pipeline.lastThread());
  out.setGiveBack([bus = last_bus.get()](LocalBus::Bytes&& b) { bus->giveBack(std::move(b)); });
  last_bus->setSink([&recorder](const std::string& channel, LocalBus::Bytes&& data) {
    recorder.handleMessage(channel, std::move(data));
  });

  LogReader in(in_path);
  ReplayMeter meter(in.fileSize());  // progress and speed on stderr; never in the output log
  int64_t events = 0, dropped = 0;
  // On the first thread: the input events, without the derived channels.
  const auto next = [&]() -> std::optional<StagePipeline::InputView> {
    while (const auto ev = in.nextView()) {
      ++events;
      if (const std::string line = meter.update(ev->timestamp, in.bytesRead()); !line.empty())
        std::cerr << "lasonic-replay: " << line << std::endl;
      if (derived.count(ev->channel)) {
        ++dropped;
        continue;
      }
      return StagePipeline::InputView{ev->timestamp, ev->channel, ev->data, ev->size};  // (valid until the next call)
    }
    return std::nullopt;
  };
  pipeline.run(next, [&recorder](int64_t timestamp) { recorder.timestamp = timestamp; });
  out.flush();
  if (events == 0) {  // nothing to replay is an error, not an empty output log
    std::cerr << "lasonic-replay: " << in_path << ": no LCM event in the file (" << out_path
              << " holds none either)\n";
    return 2;
  }
  spdlog::info("replay: {} input events ({} derived dropped), {} events written to {}", events, dropped,
               out.events(), out_path);
  std::cerr << "lasonic-replay: " << meter.summary() << std::endl;
  if (placement->computed() + placement->reused() > 0)
    spdlog::info("replay: {} thread(s); laser scans placed {} times, shared {} times (complement and pilot on one thread)",
                 nthreads, placement->computed(), placement->reused());
  else
    spdlog::info("replay: {} thread(s); each stage places its laser scans itself", nthreads);
  for (const auto& n : nodes)
    if (n->errors() > 0) spdlog::warn("{}: {} input errors", n->name(), n->errors());
  // --status: what each stage would have said in PROCESS_STATUS at the end, one "process key
  // value" line per counter on stdout (a replay publishes no PROCESS_STATUS of its own).
  if (print_status)
    for (const auto& n : nodes) {
      std::cout << n->name() << " errors " << n->errors() << "\n";
      if (!n->status().lastError().empty()) std::cout << n->name() << " last_error " << n->status().lastError() << "\n";
      for (const auto& [key, value] : n->status().counters()) std::cout << n->name() << " " << key << " " << value << "\n";
    }
  std::cout.flush();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lasonic-replay: run the pipeline stages over a log, deterministically"};
  std::string in_path, out_path, stage_list = "complement,pilot,navigator";
  bool print_status = false, print_config = false;
  int threads = 0;
  std::vector<std::string> config_files;
  app.add_option("--in", in_path, "input LCM log (raw sensor channels; required unless --print-config)")
      ->check(CLI::ExistingFile);
  app.add_option("--out", out_path, "output LCM log (inputs plus the stages' outputs; required unless --print-config)");
  app.add_option("--config", config_files,
                 "YAML configuration (sections complement, pilot, navigator); repeat to layer overrides");
  app.add_option("--stages", stage_list,
                 "stages to run, comma-separated (complement, pilot, navigator); only their outputs are "
                 "recomputed, the others' are taken from the log")
      ->capture_default_str();
  app.add_option("--threads", threads,
                 "threads to spread the stages over (1: all on one; 0: by the machine's cores, README "
                 "\"Performance\"); the output is the same, byte for byte")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  app.add_flag("--print-config", print_config,
               "print every parameter the three stages read (their value after all --config layers and the file "
               "each came from, or `default`), as the live processes' --print-config does, then exit; reads no log");
  app.add_flag("--status", print_status,
               "at the end, print every stage's counters and errors (its PROCESS_STATUS) as 'process key value' lines");
  if (const auto rc = lasonic::parseCommandLine(app, argc, argv)) return *rc;
  if (print_config) {
    try {
      const lasonic::Config root = lasonic::Config::loadConfiguration(config_files);
      lasonic::ConfigReport report;
      // (What replay() reads: every stage's configuration, whichever stages run.)
      complementConfig(root.section("complement"));
      pilotConfigFromRoot(root);
      navigatorConfigFromRoot(root);
      std::cout << lasonic::configReportForProgram("lasonic-replay", report.entries(), config_files);
      return 0;
    } catch (const lasonic::ConfigError& e) {
      std::cerr << "lasonic-replay: " << e.what() << "\n";
      return 2;
    }
  }
  for (const auto& [option, value] : {std::pair<const char*, const std::string*>{"--in", &in_path}, {"--out", &out_path}})
    if (value->empty()) {
      std::cerr << "lasonic-replay: " << option << " is required (lasonic-replay --help lists the options)\n";
      return lasonic::kExitBadCommandLine;
    }
  std::set<std::string> stages;
  for (size_t a = 0; a <= stage_list.size();) {
    const size_t b = std::min(stage_list.find(',', a), stage_list.size());
    const std::string s = stage_list.substr(a, b - a);
    if (std::none_of(kStages.begin(), kStages.end(), [&](const StageInfo& k) { return s == k.name; })) {
      std::cerr << "lasonic-replay: --stages: unknown stage '" << s << "' (complement, pilot, navigator)\n";
      return 2;
    }
    stages.insert(s);
    a = b + 1;
  }
  // The output is opened (truncated) before the input is read: the same file would be lost.
  if (lasonic::sameExistingFile(out_path, in_path)) {
    std::cerr << "lasonic-replay: --out " << out_path << " is the input log (--in " << in_path
              << "): writing it would destroy it\n";
    return 2;
  }
  for (const std::string& c : config_files)
    if (lasonic::sameExistingFile(out_path, c)) {
      std::cerr << "lasonic-replay: --out " << out_path << " is the --config file " << c << ": not overwritten\n";
      return 2;
    }
  lasonic::setupLogging("lasonic-replay");
  try {
    const lasonic::Config root = lasonic::Config::loadConfiguration(config_files);
    // Auto: a thread per stage from two cores up (three stages and the log writer). On two cores
    // two threads were fastest while the pilot was the most work; since the navigator's scan
    // matching the navigator is, and sharing its thread with the complement costs more than a
    // third thread's hand-overs (README "Performance"); on one core, one.
    if (threads == 0) {
      const unsigned cores = std::thread::hardware_concurrency();
      threads = cores >= 2 ? 3 : 1;
    }
    return replay(in_path, out_path, root, stages, threads, print_status);
  } catch (const lasonic::ConfigError& e) {
    std::cerr << "lasonic-replay: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "lasonic-replay: " << e.what() << "\n";
    return 1;
  }
}
