// One source of truth for configuration (README "Configuration"): every key of the shipped
// deploy/config/lasonic.yaml that a process reads equals the code's default, so a process started
// without --config behaves exactly as shipped, and a table made with the shipped file describes
// the code. (A key present in the file but read by nobody is an error of its section's allowOnly.)
#include <gtest/gtest.h>

#include <string>

#include "complement/complement_config.hpp"
#include "core/config.hpp"
#include "eval/baselines.hpp"
#include "sim/drivers.hpp"
#include "stages/navigator_stage.hpp"
#include "stages/pilot_stage.hpp"

using namespace lasonic;

namespace {
const Config& shipped() {
  static const Config c = Config::loadFile(std::string(LASONIC_SOURCE_DIR) + "/deploy/config/lasonic.yaml");
  return c;
}
std::string describe(const DefaultsAudit& a) {
  std::string s;
  for (const auto& m : a.mismatches()) s += "  " + m.key + ": code " + m.code_default + ", shipped " + m.value + "\n";
  return s;
}
}  // namespace

TEST(ShippedConfig, TheAuditSeesADifferentDefault) {
  // The check below could fail: a value other than the default is reported with its key path.
  DefaultsAudit audit;
  navigatorConfig(Config::fromString("navigator: {publish_hz: 3}").section("navigator"));
  ASSERT_EQ(audit.mismatches().size(), 1u);
  EXPECT_EQ(audit.mismatches()[0].key, "navigator.publish_hz");
}

TEST(ShippedConfig, CodeDefaultsAreTheShippedValues) {
  DefaultsAudit audit;
  complement::complementConfig(shipped().section("complement"));
  pilotConfig(shipped().section("pilot"));
  navigatorConfig(shipped().section("navigator"));
  eval::baselinesConfig(shipped());
  sim::laserConfig(shipped().section("laser"));
  sim::sonarConfig(shipped().section("sonar"));
  sim::odometryConfig(shipped().section("odometry"));
  EXPECT_TRUE(audit.mismatches().empty()) << "code defaults that differ from deploy/config/lasonic.yaml:\n"
                                          << describe(audit);
}
