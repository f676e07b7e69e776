#pragma once
// Airborne ultrasound for the physical sonar model (README "Sensor models"): how strong an echo
// is, in dB, against the ranging module's detection threshold. Pure functions and one small
// table class, so each term can be tested on its own.
//
// An echo is detected when its margin (dB above the threshold) is >= 0. Every margin is built
// from the same budget:
//
//   margin = planeMargin(r)                 a perfect flat mirror at normal incidence, on the
//                                           axis, at range r: spreading of the image source,
//                                           air absorption, the time-varying gain
//          + 2 * directivity(off-axis)      the transducer sends and receives
//          + reflector term                 plane 0, cylinder, edge, rough patch (below)
//          + material terms                 reflection loss, coherent / incoherent share
#include <vector>

#include "core/physics.hpp"

namespace lasonic::sim::acoustics {

using lasonic::kSpeedOfSound;  // [m/s] core/physics.hpp

// Atmospheric absorption of sound [dB/m], ISO 9613-1:1993 (pure-tone formula), for a frequency
// [Hz], temperature [°C], relative humidity [%] and pressure [kPa]. 49.4 kHz at 20 °C, 50 % RH:
// 1.64 dB/m; 40 kHz: 1.32 dB/m.
double airAbsorptionDbPerM(double frequency_hz, double temperature_c = 20.0, double humidity_pct = 50.0,
                           double pressure_kpa = 101.325);

// One-way far-field directivity of a baffled circular piston, 20 log10 |2 J1(x) / x| with
// x = ka sin(angle): 0 dB on the axis, the first null at ka sin(angle) = 3.83, side lobes of
// -17.6, -23.8, -28.0 dB. Very negative (-300 dB) at a null.
double pistonDirectivityDb(double ka, double angle);

// The transducer's directivity as a table, averaged over the pulse's band (a burst of n cycles
// spans about f/n, which fills the nulls of the single-frequency pattern). beam_scale stretches
// the pattern in angle (1.2: every lobe 20 % wider) — the simulated transducer may differ from
// the beam the driver publishes.
class Transducer {
 public:
  Transducer(double frequency_hz, double radius_m, int pulse_cycles, bool side_lobes, double beam_scale);

  // One-way directivity [dB] at an angle off the axis [rad] (any sign); -300 beyond 90°, and
  // beyond the first null when side lobes are off.
  double oneWayDb(double off_axis) const;
  // Largest off-axis angle at which 2 * oneWayDb >= -margin_db (the widest the beam can reach
  // for an echo that is margin_db above the threshold on the axis).
  double reach(double margin_db) const;
  // ∫ 10^(4 D(θ)/20) dθ [rad]: the angular width over which a spread-out reflector answers
  // (round trip, power), used for the area of a rough patch.
  double effectiveWidth() const { return effective_width_; }
  double wavelength() const { return wavelength_; }
  double wavenumber() const { return wavenumber_; }
  // Half the pulse length in range [m]: echoes closer than this arrive together.
  double pulseCell() const { return pulse_cell_; }
  // First null of the (unscaled pattern × beam_scale), [rad]; 90° if none.
  double firstNull() const { return first_null_; }

 private:
  static constexpr double kStep = 0.001;   // [rad] table resolution (0.06°)
  std::vector<double> table_;              // dB at i * kStep, 0 .. pi/2
  double wavelength_, wavenumber_, pulse_cell_, effective_width_, first_null_;
  double scale_ = 1.0;
};

// Coherent (mirror-like) share of the reflected power of a surface with rms height h [m] at
// normal incidence, exp(-(2 k h)^2) (the Rayleigh roughness criterion, Beckmann & Spizzichino
// 1963). The rest is scattered incoherently.
double coherentShare(double wavenumber, double rms_height);

// Incoherent backscattering coefficient sigma0 (per unit area, 4π convention) at incidence
// beta: a share `diffuse` scattered as Lambert's law, 4 cos² beta, the rest as the
// geometric-optics specular lobe of a surface with rms facet slope tan(lobe),
// exp(-tan² beta / 2 s²) / (2 s² cos⁴ beta).
double incoherentBackscatter(double beta, double lobe, double diffuse);

// Margin terms relative to a flat mirror at the same range [dB]:
// a long vertical cylinder of radius a seen at range r (to its surface): ray optics of a convex
// mirror, 10 log10(a / (a + r));
double cylinderDb(double radius, double range);
// a straight edge (the end of a pane, a box corner) at range r: backscatter diffraction of a
// half-plane, 10 log10(lambda / (8 pi² r)) (about -41 dB at 1 m for 49.4 kHz);
double edgeDb(double wavelength, double range);
// a rough patch at range r and incidence beta whose incoherent coefficient is sigma0: the area
// that answers within one pulse cell (vertical: r * width, horizontal: the pulse cell / sin beta
// or the beam's footprint, whichever is smaller) as sigma0 * area / (pi r²).
double patchDb(double sigma0, double range, double beta, double beam_width, double pulse_cell);

// The margin of a perfect flat mirror at normal incidence on the transducer's axis, range r [m]:
// the image source at 2r (spherical spreading, -20 log10 r relative to 1 m), air absorption on
// the way there and back, and the receiver's time-varying gain (TVG): below tvg_range the gain
// is lowered just as much as a plane's echo is stronger there, so that near clutter and the
// transducer's ring-down do not trigger it. snr_db is the margin at 1 m with full gain; it is
// set from the range at which a flat wall is just detected (the module's specified maximum):
// planeMargin(plane_range) = 0.
class EchoBudget {
 public:
  EchoBudget(double plane_range, double absorption_db_per_m, double tvg_range);
  // Spreading and absorption along a one-way path of `path` metres from the source and back to
  // the receiver ... as a margin at full gain: for an echo at range r, path = 2r.
  double pathDb(double path) const;
  // Gain of the receiver at the time an echo from range r arrives, relative to full gain (<= 0).
  double tvgDb(double range) const;
  // pathDb(2r) + tvgDb(r) + snr.
  double planeMargin(double range) const { return snr_ + pathDb(2 * range) + tvgDb(range); }
  double snr() const { return snr_; }
  double absorption() const { return absorption_; }
  // Largest range at which anything can still be heard (a flat mirror on the axis).
  double hearingRange() const { return plane_range_; }

 private:
  double plane_range_, absorption_, tvg_range_, snr_;
};

}  // namespace lasonic::sim::acoustics
