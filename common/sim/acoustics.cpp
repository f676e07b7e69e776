#include "sim/acoustics.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>
#include <tuple>

namespace lasonic::sim::acoustics {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kFloorDb = -300.0;
constexpr double kFirstZeroJ1 = 3.8317059702075125;  // first zero of J1

double toDb(double power_ratio) { return power_ratio > 1e-30 ? 10.0 * std::log10(power_ratio) : kFloorDb; }

// |2 J1(x) / x|², the piston's one-way power pattern.
double pistonPower(double x) {
  if (std::abs(x) < 1e-9) return 1.0;
  const double v = 2.0 * std::cyl_bessel_j(1.0, std::abs(x)) / std::abs(x);
  return v * v;
}
}  // namespace

double airAbsorptionDbPerM(double f, double temperature_c, double humidity_pct, double pressure_kpa) {
  // ISO 9613-1:1993, equations (3)-(5) and annex B (saturation vapour pressure).
  const double pr = 101.325, t0 = 293.15, t01 = 273.16;
  const double t = temperature_c + 273.15;
  const double pa = pressure_kpa;
  const double c = -6.8346 * std::pow(t01 / t, 1.261) + 4.6151;
  const double h = humidity_pct * std::pow(10.0, c) * (pr / pa);  // molar concentration of water vapour [%]
  const double fr_o = pa / pr * (24.0 + 4.04e4 * h * (0.02 + h) / (0.391 + h));
  const double fr_n = pa / pr * std::pow(t / t0, -0.5) * (9.0 + 280.0 * h * std::exp(-4.170 * (std::pow(t / t0, -1.0 / 3.0) - 1.0)));
  return 8.686 * f * f *
         (1.84e-11 * (pr / pa) * std::sqrt(t / t0) +
          std::pow(t / t0, -2.5) * (0.01275 * std::exp(-2239.1 / t) / (fr_o + f * f / fr_o) +
                                    0.1068 * std::exp(-3352.0 / t) / (fr_n + f * f / fr_n)));
}

namespace {
// The band-averaged table, 0 .. pi/2 in steps of `step`. Shared between transducers of the same
// kind (tests and tools build many models of one transducer).
std::vector<double> directivityTable(double ka, int pulse_cycles, bool side_lobes, double null_angle, double step) {
  using Key = std::tuple<double, int, bool, double, double>;
  static std::mutex mutex;
  static std::map<Key, std::vector<double>> cache;
  const Key key{ka, pulse_cycles, side_lobes, null_angle, step};
  std::lock_guard<std::mutex> lock(mutex);
  if (auto it = cache.find(key); it != cache.end()) return it->second;
  // The burst's spectrum: sinc² around f, main lobe f (1 ± 1/n); 11 samples of it.
  constexpr int kBand = 5;
  std::vector<double> kas, weights;
  double wsum = 0;
  for (int i = -kBand; i <= kBand; ++i) {
    const double d = static_cast<double>(i) / (kBand * pulse_cycles);  // relative frequency offset
    const double s = std::abs(d) < 1e-12 ? 1.0 : std::sin(kPi * d * pulse_cycles) / (kPi * d * pulse_cycles);
    kas.push_back(ka * (1.0 + d));
    weights.push_back(s * s);
    wsum += s * s;
  }
  const size_t n = static_cast<size_t>(std::ceil((kPi / 2) / step)) + 1;
  std::vector<double> table(n);
  for (size_t i = 0; i < n; ++i) {
    const double a = std::min(static_cast<double>(i) * step, kPi / 2);
    double p = 0;
    for (size_t j = 0; j < kas.size(); ++j) p += weights[j] * pistonPower(kas[j] * std::sin(a));
    table[i] = (!side_lobes && a > null_angle) ? kFloorDb : toDb(p / wsum);
  }
  return cache.emplace(key, std::move(table)).first->second;
}
}  // namespace

double pistonDirectivityDb(double ka, double angle) {
  return toDb(pistonPower(ka * std::sin(std::min(std::abs(angle), kPi / 2))));
}

Transducer::Transducer(double frequency_hz, double radius_m, int pulse_cycles, bool side_lobes, double beam_scale) {
  if (!(frequency_hz > 0 && radius_m > 0 && pulse_cycles > 0 && beam_scale > 0))
    throw std::invalid_argument("Transducer: frequency, radius, pulse cycles and beam scale must be > 0");
  wavelength_ = kSpeedOfSound / frequency_hz;
  wavenumber_ = 2.0 * kPi / wavelength_;
  pulse_cell_ = 0.5 * kSpeedOfSound * pulse_cycles / frequency_hz;
  const double ka = wavenumber_ * radius_m;
  first_null_ = ka > kFirstZeroJ1 ? std::asin(kFirstZeroJ1 / ka) * beam_scale : kPi / 2;

  table_ = directivityTable(ka, pulse_cycles, side_lobes, first_null_ / beam_scale, kStep);
  const size_t n = table_.size();
  // ∫ D⁴ over the (scaled) pattern, -90°..90°.
  double w = 0;
  for (size_t i = 0; i < n; ++i) {
    const double a = static_cast<double>(i) * kStep * beam_scale;
    if (a > kPi / 2) break;
    w += 2.0 * std::pow(10.0, 4.0 * table_[i] / 20.0) * kStep * beam_scale;
  }
  effective_width_ = w;
  table_.push_back(kFloorDb);  // sentinel: beyond 90°
  scale_ = beam_scale;
}

double Transducer::oneWayDb(double off_axis) const {
  // Nothing behind the transducer's face, however wide the (scaled) pattern.
  if (!(std::abs(off_axis) <= kPi / 2)) return kFloorDb;
  const double a = std::abs(off_axis) / scale_;
  if (!(a <= kPi / 2)) return kFloorDb;
  const double f = a / kStep;
  const size_t i = static_cast<size_t>(f);
  if (i + 1 >= table_.size()) return table_.back();
  const double t = f - static_cast<double>(i);
  // Linear in dB between table points, except next to a floored null.
  if (table_[i] <= kFloorDb + 1 || table_[i + 1] <= kFloorDb + 1) return std::min(table_[i], table_[i + 1]);
  return table_[i] + t * (table_[i + 1] - table_[i]);
}

double Transducer::reach(double margin_db) const {
  for (size_t i = table_.size() - 1; i-- > 0;)
    if (2.0 * table_[i] >= -margin_db) return std::min(kPi / 2, static_cast<double>(i + 1) * kStep * scale_);
  return 0.0;
}

double coherentShare(double wavenumber, double rms_height) {
  const double g = 2.0 * wavenumber * rms_height;
  return std::exp(-g * g);
}

double incoherentBackscatter(double beta, double lobe, double diffuse) {
  const double c = std::cos(beta);
  double out = diffuse * 4.0 * c * c;
  if (diffuse < 1.0 && lobe > 0 && c > 1e-6) {
    const double s = std::tan(lobe), t = std::tan(beta);
    out += (1.0 - diffuse) * std::exp(-t * t / (2.0 * s * s)) / (2.0 * s * s * c * c * c * c);
  }
  return out;
}

double cylinderDb(double radius, double range) { return toDb(radius / (radius + std::max(range, 0.0))); }

double edgeDb(double wavelength, double range) { return toDb(wavelength / (8.0 * kPi * kPi * std::max(range, 1e-3))); }

double patchDb(double sigma0, double range, double beta, double beam_width, double pulse_cell) {
  const double r = std::max(range, 1e-3);
  const double sb = std::abs(std::sin(beta)), cb = std::max(std::cos(beta), 1e-6);
  const double horizontal = std::min(sb > 1e-9 ? pulse_cell / (r * sb) : 1e9, beam_width / cb);  // [rad]
  const double area_over_r2 = beam_width * horizontal;  // vertical footprint (r * width) × horizontal / r²
  return toDb(sigma0 * area_over_r2 / kPi);
}

EchoBudget::EchoBudget(double plane_range, double absorption_db_per_m, double tvg_range)
    : plane_range_(plane_range), absorption_(absorption_db_per_m), tvg_range_(tvg_range) {
  if (!(plane_range > 0 && absorption_db_per_m >= 0 && tvg_range >= 0))
    throw std::invalid_argument("EchoBudget: plane_range > 0, absorption >= 0, tvg_range >= 0");
  snr_ = -pathDb(2 * plane_range);
}

double EchoBudget::pathDb(double path) const {
  const double p = std::max(path, 1e-6);
  return -20.0 * std::log10(p / 2.0) - absorption_ * (p - 2.0);
}

double EchoBudget::tvgDb(double range) const {
  if (range >= tvg_range_) return 0.0;
  return pathDb(2 * tvg_range_) - pathDb(2 * std::max(range, 1e-6));
}

}  // namespace lasonic::sim::acoustics
