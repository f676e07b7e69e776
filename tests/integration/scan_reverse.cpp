// lasonic-scan-reverse IN OUT: IN with every LASER_SCAN as a clockwise scanner would have sent
// the same readings: the arrays reversed (each reading keeps its own time offset), angle_min
// the last reading's angle, angle_increment negated; its LASER_TRUTH's per-reading obstacles
// reversed with it. Every other event is copied as it is.
// Used by clockwise_scan.sh: the pipeline must read such a log as the original.
#include <algorithm>
#include <cstdio>
#include <string>

#include <lasonic/laser_scan_t.hpp>
#include <lasonic/laser_truth_t.hpp>

#include "lcmio/eventlog.hpp"

using namespace lasonic;

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: lasonic-scan-reverse IN OUT\n");
    return 2;
  }
  try {
    LogReader in(argv[1]);
    LogWriter out(argv[2]);
    long scans = 0;
    while (auto ev = in.next()) {
      if (ev->channel == "LASER_SCAN") {
        auto m = decodeAs<laser_scan_t>(ev->data);
        if (!m || m->ranges.empty()) {
          std::fprintf(stderr, "lasonic-scan-reverse: a LASER_SCAN that does not decode\n");
          return 1;
        }
        const size_t n = m->ranges.size();
        std::reverse(m->ranges.begin(), m->ranges.end());
        std::reverse(m->flags.begin(), m->flags.end());
        std::reverse(m->offset_us.begin(), m->offset_us.end());
        m->angle_min += static_cast<double>(n - 1) * m->angle_increment;
        m->angle_increment = -m->angle_increment;
        out.write(ev->channel, ev->timestamp, *m);
        ++scans;
      } else if (ev->channel == "LASER_TRUTH") {
        auto t = decodeAs<laser_truth_t>(ev->data);
        if (!t) {
          std::fprintf(stderr, "lasonic-scan-reverse: a LASER_TRUTH that does not decode\n");
          return 1;
        }
        std::reverse(t->obstacle.begin(), t->obstacle.end());
        out.write(ev->channel, ev->timestamp, *t);
      } else {
        out.writeRaw(ev->channel, ev->timestamp, ev->data);
      }
    }
    out.flush();
    std::printf("lasonic-scan-reverse: %ld scans reversed\n", scans);
  } catch (const LogError& e) {
    std::fprintf(stderr, "lasonic-scan-reverse: %s\n", e.what());
    return 1;
  }
  return 0;
}
