// Airborne ultrasound terms of the physical sonar model (sim/acoustics.hpp).
#include <gtest/gtest.h>

#include <cmath>

#include "core/geometry.hpp"
#include "sim/acoustics.hpp"

using namespace lasonic::sim::acoustics;
using lasonic::geom::deg2rad;

TEST(Acoustics, AirAbsorptionFollowsIso9613) {
  // ISO 9613-1 at 20 °C, 101.325 kPa: 49.4 kHz (the Polaroid module) and 40 kHz (Murata-type).
  EXPECT_NEAR(airAbsorptionDbPerM(49'400, 20, 50), 1.64, 0.01);
  EXPECT_NEAR(airAbsorptionDbPerM(40'000, 20, 50), 1.32, 0.01);
  EXPECT_NEAR(airAbsorptionDbPerM(49'400, 20, 30), 1.25, 0.01);
  // Classic reference point of the standard's table: 1 kHz, 20 °C, 50 %: about 5 dB/km.
  EXPECT_NEAR(airAbsorptionDbPerM(1'000, 20, 50) * 1000, 4.7, 0.3);
  EXPECT_GT(airAbsorptionDbPerM(60'000), airAbsorptionDbPerM(50'000));
}

TEST(Acoustics, PistonDirectivityHasItsNullsAndSideLobes) {
  const double ka = 17.37;  // Polaroid 600 series at 49.4 kHz: a = 19.2 mm
  EXPECT_NEAR(pistonDirectivityDb(ka, 0), 0.0, 1e-12);
  // First null at ka sin = 3.832: 12.7°.
  EXPECT_LT(pistonDirectivityDb(ka, std::asin(3.8317 / ka)), -60);
  // First side lobe at ka sin = 5.136: -17.6 dB; second at 8.417: -23.8 dB.
  EXPECT_NEAR(pistonDirectivityDb(ka, std::asin(5.1356 / ka)), -17.57, 0.05);
  EXPECT_NEAR(pistonDirectivityDb(ka, std::asin(8.4172 / ka)), -23.81, 0.05);
  // -3 dB at ka sin = 1.616 (5.3°).
  EXPECT_NEAR(pistonDirectivityDb(ka, std::asin(1.6163 / ka)), -3.01, 0.05);
}

TEST(Acoustics, TransducerTableFillsNullsAndScales) {
  const Transducer t(49'400, 0.0192, 16, true, 1.0);
  EXPECT_NEAR(t.wavelength(), 343.0 / 49'400, 1e-12);
  EXPECT_NEAR(t.pulseCell(), 0.5 * 343.0 * 16 / 49'400, 1e-12);  // 5.6 cm
  EXPECT_NEAR(t.firstNull(), deg2rad(12.7), deg2rad(0.1));
  EXPECT_NEAR(t.oneWayDb(0), 0.0, 1e-9);
  EXPECT_NEAR(t.oneWayDb(deg2rad(5.3)), -3.0, 0.2);
  EXPECT_DOUBLE_EQ(t.oneWayDb(deg2rad(5)), t.oneWayDb(deg2rad(-5)));
  // The 16-cycle burst spans ±1/16 of the frequency: the null is filled, but stays deep.
  const double null_db = t.oneWayDb(t.firstNull());
  EXPECT_GT(null_db, -60);
  EXPECT_LT(null_db, -20);
  EXPECT_NEAR(t.oneWayDb(deg2rad(17.2)), -17.6, 1.0);  // side lobe
  EXPECT_LT(t.oneWayDb(deg2rad(91)), -200);          // behind the transducer
  // Without side lobes nothing is heard beyond the first null.
  const Transducer main_only(49'400, 0.0192, 16, false, 1.0);
  EXPECT_LT(main_only.oneWayDb(deg2rad(17.2)), -200);
  EXPECT_NEAR(main_only.oneWayDb(deg2rad(5.3)), t.oneWayDb(deg2rad(5.3)), 1e-12);
  // beam_scale stretches the pattern: 20 % wider, every angle.
  const Transducer wide(49'400, 0.0192, 16, true, 1.2);
  for (double a : {2.0, 5.0, 9.0, 17.0})
    EXPECT_NEAR(wide.oneWayDb(deg2rad(1.2 * a)), t.oneWayDb(deg2rad(a)), 0.05) << a;
  EXPECT_NEAR(wide.firstNull(), 1.2 * t.firstNull(), 1e-9);
  // A wider pattern still sends nothing behind the transducer's face.
  EXPECT_GT(wide.oneWayDb(deg2rad(89)), -100);
  EXPECT_LT(wide.oneWayDb(deg2rad(95)), -200);
  EXPECT_NEAR(wide.effectiveWidth(), 1.2 * t.effectiveWidth(), 0.01 * t.effectiveWidth());
  // The reach grows with the echo's margin: more than the main lobe only for strong echoes.
  EXPECT_LT(t.reach(10), t.reach(30));
  EXPECT_LT(t.reach(30), t.firstNull());
  EXPECT_GT(t.reach(50), deg2rad(25));  // the second side lobe (28.9°, -47.6 dB round trip)
  // Round-trip power pattern integrated: about 0.1 rad for this transducer.
  EXPECT_GT(t.effectiveWidth(), 0.05);
  EXPECT_LT(t.effectiveWidth(), 0.2);
}

TEST(Acoustics, EchoBudgetIsCalibratedOnTheWallRange) {
  const double alpha = airAbsorptionDbPerM(49'400);
  const EchoBudget b(10.7, alpha, 1.0);
  EXPECT_NEAR(b.planeMargin(10.7), 0.0, 1e-9);  // a flat wall is just heard at 10.7 m
  EXPECT_NEAR(b.snr(), 20 * std::log10(10.7) + 2 * alpha * 9.7, 1e-9);
  // The time-varying gain holds a plane's margin constant below 1 m, then it falls with
  // spreading and absorption.
  EXPECT_NEAR(b.planeMargin(0.2), b.planeMargin(1.0), 1e-9);
  EXPECT_NEAR(b.planeMargin(0.6), b.snr(), 1e-9);
  EXPECT_NEAR(b.planeMargin(2.0), b.snr() - 20 * std::log10(2.0) - 2 * alpha, 1e-9);
  EXPECT_LT(b.planeMargin(3.0), b.planeMargin(2.0));
  EXPECT_LT(b.tvgDb(0.5), 0);
  EXPECT_DOUBLE_EQ(b.tvgDb(1.5), 0);
  // A one-way path of L metres (emitter -> reflector -> receiver) as a mirror at L / 2.
  EXPECT_NEAR(b.pathDb(6.0) + b.snr(), b.planeMargin(3.0) - b.tvgDb(3.0), 1e-9);
}

TEST(Acoustics, ReflectorTerms) {
  const double k = 2 * M_PI / (343.0 / 49'400);
  // Rayleigh roughness: painted plaster (0.2 mm) is 88 % mirror at 49.4 kHz; 3 mm is all scatter.
  EXPECT_NEAR(coherentShare(k, 0.2e-3), 0.877, 0.005);
  EXPECT_LT(coherentShare(k, 3e-3), 1e-10);
  EXPECT_DOUBLE_EQ(coherentShare(k, 0), 1.0);
  // A 1 cm pipe at 1.5 m: 22 dB below a wall; a 0.25 m person 8 dB; an edge at 1 m 41 dB.
  EXPECT_NEAR(cylinderDb(0.01, 1.5), -21.8, 0.1);
  EXPECT_NEAR(cylinderDb(0.25, 1.5), -8.45, 0.1);
  EXPECT_NEAR(edgeDb(343.0 / 49'400, 1.0), -40.6, 0.1);
  EXPECT_LT(edgeDb(343.0 / 49'400, 2.0), edgeDb(343.0 / 49'400, 1.0));
  // Lambert's law falls as cos²; a narrow specular lobe is strong at normal incidence only.
  EXPECT_NEAR(incoherentBackscatter(0, 0.1, 1.0), 4.0, 1e-12);
  EXPECT_NEAR(incoherentBackscatter(deg2rad(60), 0.1, 1.0), 1.0, 1e-9);
  const double lobe = deg2rad(5);
  EXPECT_GT(incoherentBackscatter(0, lobe, 0), 50);
  EXPECT_LT(incoherentBackscatter(deg2rad(20), lobe, 0), 1e-3 * incoherentBackscatter(0, lobe, 0));
  // A rough patch answers less at oblique incidence and from farther away.
  const double w = 0.1, cell = 0.056;
  EXPECT_GT(patchDb(4.0, 1.0, deg2rad(20), w, cell), patchDb(4.0, 1.0, deg2rad(60), w, cell));
  EXPECT_GT(patchDb(4.0, 1.0, deg2rad(45), w, cell), patchDb(4.0, 2.0, deg2rad(45), w, cell));
}
