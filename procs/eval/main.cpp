// lasonic-eval: scores a log against the simulator's truth (README "Evaluation"), lasonic's maps
// and the baselines' (computed here from the log's raw channels, configured by --config).
#include <CLI/CLI.hpp>

#include <fstream>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "core/cli.hpp"
#include "core/config.hpp"
#include "core/same_file.hpp"
#include "eval/baselines.hpp"
#include "eval/evaluate.hpp"
#include "lcmio/eventlog.hpp"

int main(int argc, char** argv) {
  CLI::App app{"lasonic-eval: score an LCM log against the simulator's ground truth"};
  std::string log_path, scenario_path, json_path;
  std::vector<std::string> config_files;
  app.add_option("--log", log_path, "LCM log (from lasonic-sim, lasonic-replay or lcm-logger)")->required();
  app.add_option("--scenario", scenario_path, "scenario YAML the log was simulated from")->required();
  app.add_option("--json", json_path, "also write the metrics as JSON to FILE ('-' = standard output)");
  app.add_option("--config", config_files,
                 "YAML configuration the log was replayed with (sections pilot and baselines: the baselines' "
                 "parameters and read-out; navigator: the breakdown's line generation; repeat to layer overrides); without it the code's defaults");
  bool breakdown = false;
  app.add_flag("--breakdown", breakdown,
               "also say why located points are missed by the tactical AGM and its lines "
               "(agm_tactical.breakdown.*, lines.breakdown.*)");
  std::string samples_path;
  app.add_option("--samples", samples_path,
                 "also write every scored sector sample of SECTOR_MAP as CSV to FILE (time, sector, truth, "
                 "reported value and source, each source's value, material, observability cue, missed, false alarm, "
                 "the truth's point and obstacle)");
  std::string tactical_samples_path;
  app.add_option("--tactical-samples", tactical_samples_path,
                 "also write every sample of the tactical breakdown as CSV to FILE (time, true position, "
                 "obstacle and material of a located laser-invisible boundary point; whether the tactical AGM "
                 "holds it and else why not; whether a sonar line covers it and else why not); implies --breakdown");
  std::string complement_samples_path;
  app.add_option("--complement-samples", complement_samples_path,
                 "also write every classified sonar reading of SONAR_COMPLEMENT as CSV to FILE (time, sensor, "
                 "range, true cause, range and surface, what the laser saw, hypothetical range, class; for each "
                 "complement.* rate it counts in, 1 if it counted as right, 0 if not)");
  if (const auto rc = lasonic::parseCommandLine(app, argc, argv)) return *rc;
  // No output over an input (README "Scenario format", *Physical bounds*): --json naming the log
  // would truncate it before it is read.
  {
    std::vector<std::pair<std::string, std::string>> inputs = {{"--log", log_path}, {"--scenario", scenario_path}};
    for (const std::string& c : config_files) inputs.emplace_back("--config", c);
    const std::pair<const char*, std::string> outputs[] = {
        {"--json", json_path == "-" ? std::string() : json_path},
        {"--samples", samples_path},
        {"--tactical-samples", tactical_samples_path},
        {"--complement-samples", complement_samples_path}};
    for (const auto& [option, out] : outputs)
      for (const auto& [input_option, input] : inputs)
        if (!out.empty() && lasonic::sameExistingFile(out, input)) {
          std::cerr << "lasonic-eval: " << option << " " << out << " is the " << input_option << " file " << input
                    << ": not overwritten\n";
          return 2;
        }
  }
  lasonic::eval::BaselinesConfig baselines;
  lasonic::eval::EvalOptions opts;
  try {
    const auto config = lasonic::Config::loadConfiguration(config_files);
    baselines = lasonic::eval::baselinesConfig(config);
    opts = lasonic::eval::evalOptions(config);  // the breakdown redoes the run's line generation
  } catch (const lasonic::ConfigError& e) {
    std::cerr << "lasonic-eval: bad config: " << e.what() << "\n";
    return 2;
  }
  try {
    const auto scenario = lasonic::sim::loadScenario(scenario_path);
    const auto log = lasonic::eval::loadRunLog(log_path);
    if (log.empty()) {  // nothing to score is an error, not an empty table (as lasonic-render says)
      std::cerr << "lasonic-eval: " << log_path << ": no lasonic message on any scored channel"
                << (log.undecodable > 0 ? " (" + std::to_string(log.undecodable) + " did not decode)" : std::string()) << "\n";
      return 2;
    }
    if (log.sim_states.empty())
      std::cerr << "lasonic-eval: warning: " << log_path << " holds no SIM_STATE: truth-based scores are skipped\n";
    // Scored against a scenario it was not simulated from, a log gives numbers that mean nothing.
    if (const auto match = lasonic::eval::checkLogMatchesScenario(log, scenario); !match.error.empty()) {
      std::cerr << "lasonic-eval: " << log_path << " was not simulated from " << scenario_path << ": " << match.error << "\n";
      return 2;
    } else if (!match.warning.empty()) {
      std::cerr << "lasonic-eval: warning: " << log_path << " against " << scenario_path << ": " << match.warning
                << " (was it simulated from this scenario?)\n";
    }
    if (const std::string w = lasonic::eval::robotRadiusWarning(log, scenario); !w.empty())
      std::cerr << "lasonic-eval: warning: " << log_path << ": " << w << "\n";
    if (log.undecodable > 0)
      std::cerr << "lasonic-eval: warning: " << log.undecodable << " events did not decode and were skipped\n";
    opts.breakdown = breakdown || !tactical_samples_path.empty();
    // A CSV file asked for (path not empty), opened with its header; false if it cannot be written.
    const auto openCsv = [](const std::string& path, std::ofstream& out, void (*header)(std::ostream&),
                            std::ostream*& target) {
      if (path.empty()) return true;
      out.open(path);
      if (!out) {
        std::cerr << "lasonic-eval: cannot write " << path << "\n";
        return false;
      }
      header(out);
      target = &out;
      return true;
    };
    std::ofstream tactical_samples, samples, complement_samples;
    if (!openCsv(tactical_samples_path, tactical_samples, lasonic::eval::writeTacticalSampleHeader,
                 opts.tactical_samples_csv) ||
        !openCsv(samples_path, samples, lasonic::eval::writeSectorSampleHeader, opts.samples_csv) ||
        !openCsv(complement_samples_path, complement_samples, lasonic::eval::writeComplementSampleHeader,
                 opts.complement_samples_csv))
      return 1;
    const auto metrics = lasonic::eval::evaluate(log, scenario, opts, &baselines);
    // Never silently: without the laser's truth "laser-invisible" falls back to the material.
    if (metrics.has("sensors.laser_truth") && metrics.number("sensors.laser_truth") == 0 &&
        (!log.sonar_truths.empty() || !log.agm_tactical.empty() || !log.agm_operational.empty()))
      std::cerr << "lasonic-eval: warning: " << log_path << " holds no LASER_TRUTH (or no SIM_STATE): "
                << "laser-invisible is decided by material, not by what the laser saw (sensors.laser_truth = 0)\n";
    if (json_path == "-") {
      std::cout << metrics.toJson();
      return 0;
    }
    std::cout << "lasonic-eval: " << log_path << " (scenario " << scenario.name << ")\n" << metrics.toTable();
    if (const std::string b = metrics.brief(); !b.empty())
      std::cout << "\nIn brief (README \"Evaluation\" defines each key, \"Results\" gives the targets):\n" << b;
    if (!json_path.empty()) {
      std::ofstream out(json_path);
      if (!out) {
        std::cerr << "lasonic-eval: cannot write " << json_path << "\n";
        return 1;
      }
      out << metrics.toJson();
    }
  } catch (const lasonic::ConfigError& e) {
    std::cerr << "lasonic-eval: bad scenario: " << e.what() << "\n";
    return 2;
  } catch (const lasonic::LogError& e) {
    std::cerr << "lasonic-eval: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {  // e.g. a log whose SIM_STATE does not match the scenario
    std::cerr << "lasonic-eval: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
