// lasonic-replay --in LOG --out LOG [--config FILE]
//
// Runs the pipeline stages (complement, pilot, navigator) in one process over a log's raw channels, deterministically: every
// stage has its own Node on one shared in-process bus (LocalBus: LCM's memq:// delivery order);
// each input event is published into it and the queue drained before the next, so the stages see exactly the log's order. A
// recorder on ".*" writes every message it sees (inputs and outputs) to the output log; an
// output event carries the timestamp of the input event that caused it. Channels that the
// stages produce are dropped from the input (they are recomputed), as is PROCESS_STATUS.
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <iostream>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "core/logging.hpp"
#include "lcmio/eventlog.hpp"
#include "lcmio/node.hpp"
#include "lcmio/replay_meter.hpp"
#include "stages/complement_stage.hpp"
#include "stages/navigator_stage.hpp"
#include "stages/pilot_stage.hpp"

namespace {

using namespace lasonic;

// Outputs of the stages (and of the live pipeline): never taken from the input log.
const std::set<std::string> kDerivedChannels = {
    channels::RADAR_MAP,   channels::SONAR_HYPOTHESIS, channels::SONAR_COMPLEMENT,
    channels::AGM_OPERATIONAL, channels::SECTOR_MAP,  channels::AGM_TACTICAL,
    channels::AGM_LINES,   channels::CURRENT_SENSOR_MAP, channels::PROCESS_STATUS};

struct Recorder {
  LogWriter* out = nullptr;
  int64_t timestamp = 0;  // of the input event being processed
  void handleMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    const auto* p = static_cast<const uint8_t*>(rbuf->data);
    out->writeRaw(channel, timestamp, p, rbuf->data_size);
  }
};

int replay(const std::string& in_path, const std::string& out_path, const Config& root) {
  auto lcm = std::make_shared<LocalBus>();
  const Node::Options offline{/*heartbeat=*/false, /*install_signal_handlers=*/false};

  // ---- the stages, in pipeline order. Add a stage here: its Node and its object.
  Node complement_node("lasonic-complement", lcm, offline);
  ComplementStage complement_stage(complement_node, complementConfig(root.section("complement")));
  Node pilot_node("lasonic-pilot", lcm, offline);
  PilotStage pilot_stage(pilot_node, pilotConfig(root.section("pilot")));
  Node navigator_node("lasonic-navigator", lcm, offline);
  NavigatorStage navigator_stage(navigator_node, navigatorConfig(root.section("navigator")));
  const std::vector<const Node*> nodes = {&complement_node, &pilot_node, &navigator_node};
  // ----

  LogWriter out(out_path);
  Recorder recorder{&out};
  lcm->subscribe(".*", [&recorder](const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    recorder.handleMessage(rbuf, channel);
  });

  LogReader in(in_path);
  ReplayMeter meter(in.fileSize());  // progress and speed on stderr; never in the output log
  int64_t events = 0, dropped = 0;
  while (auto ev = in.next()) {
    ++events;
    if (const std::string line = meter.update(ev->timestamp, in.bytesRead()); !line.empty())
      std::cerr << "lasonic-replay: " << line << std::endl;
    if (kDerivedChannels.count(ev->channel)) {
      ++dropped;
      continue;
    }
    recorder.timestamp = ev->timestamp;
    lcm->publish(ev->channel, ev->data.data(), ev->data.size());
    lcm->handleAll();
  }
  out.flush();
  spdlog::info("replay: {} input events ({} derived dropped), {} events written to {}", events, dropped,
               out.events(), out_path);
  std::cerr << "lasonic-replay: " << meter.summary() << std::endl;
  for (const Node* n : nodes)
    if (n->errors() > 0) spdlog::warn("{}: {} input errors", n->name(), n->errors());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lasonic-replay: run the pipeline stages over a log, deterministically"};
  std::string in_path, out_path;
  std::vector<std::string> config_files;
  app.add_option("--in", in_path, "input LCM log (raw sensor channels)")->required()->check(CLI::ExistingFile);
  app.add_option("--out", out_path, "output LCM log (inputs plus the stages' outputs)")->required();
  app.add_option("--config", config_files,
                 "YAML configuration (sections complement, pilot, navigator); repeat to layer overrides")
      ->check(CLI::ExistingFile);
  CLI11_PARSE(app, argc, argv);
  lasonic::setupLogging("lasonic-replay");
  try {
    const lasonic::Config root = lasonic::Config::loadFiles(config_files);
    return replay(in_path, out_path, root);
  } catch (const lasonic::ConfigError& e) {
    std::cerr << "lasonic-replay: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "lasonic-replay: " << e.what() << "\n";
    return 1;
  }
}
