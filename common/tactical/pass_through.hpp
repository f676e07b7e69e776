#pragma once
// Pass-through (beyond the paper; shipped): the tactical AGM forgets a remembered cell that the
// sonar has since heard through.
//
// The paper's AGM only adds: a cell is forgotten by time (h_max) alone. So what the memory took
// for a static obstacle stays for the whole memory when it has gone: a person who stood behind a
// 180 deg laser (heard, never seen, so never explained) or a crosstalk ghost. The laser cannot
// undo it (it sees through glass as through the place a person left); the sonar can, where the
// cell would have answered it. A reading's sound has passed every point of its beam nearer than
// its range (or, for a reading longer than the ideal sonar's hypothesis, than the hypothesis: a
// mirror there turned it away) with nothing there answering. A remembered cell in the middle of
// such a beam (within `core` of the beam's half width of the axis, where the transducer's gain
// is near its peak) and at least `margin_m` nearer than the reading should have answered unless:
//  - it is part of a remembered line (a plane: glass, a box side) that the beam met obliquely: a
//    plane answers only from the foot of the perpendicular, so met at an angle beyond the core it
//    is silent by physics (the glass pane passed obliquely that the memory is there for).
//    Optionally (line_heard_at_normal, off: measured, tests/RESULTS.md "Round lines") a
//    line whose cell was heard from off its normal is no plane but a round reflector's front that
//    happens to line up (a person heard from one side), passed like any cell by a beam from where
//    it was heard;
//  - the reading is silent (no echo, or none within the hypothesis' range limit) and comes from
//    elsewhere than where the cell answered before: a plane met obliquely is silent too, and a
//    pane heard sparsely is no line to the test above (heard_from_gate);
//  - the reflector is weak and answers only now and then (a mesh): so a cell is emptied only
//    once `clear_after` firing groups have passed through it since it was last hit, and by
//    silence only after as many silent looks as its answer rate makes unlikely (silence_risk); a
//    cell hit again starts counting afresh.
#include <cstdint>
#include <map>
#include <tuple>
#include <vector>

#include "core/config.hpp"
#include "core/geometry.hpp"
#include "operational/agm.hpp"
#include "operational/sound_passed.hpp"

namespace lasonic {

struct PassThroughParams {
  double core = 0.5;         // fraction of the beam's half width about the axis; 0: off (the paper)
  double margin_m = 0.25;    // [m] the cell at least this much nearer than the reading
  int clear_after = 2;       // firings in a row that passed through the cell
  double line_ratio = 0.3;   // a neighbourhood is a line when its spread across / along is below this
  int line_min_cells = 3;    // ... and it holds at least this many remembered cells
  int line_radius_cells = 2; // the neighbourhood: (2r+1) x (2r+1) cells
  // true: a line is no plane where its cell was heard from farther than a beam width off the
  // line's normal (a plane answers transducers within the half beam of its normal, and an echo
  // lands up to a half beam along its arc) by two echoes or more, for a beam from where it was
  // heard (within the half beam of that direction). Where a cell was heard from is kept only with
  // heard_from_gate and unverifiable readings; a cell without it is a plane. false: every line is
  // a plane (shipped).
  bool line_heard_at_normal = false;
  // Unverifiable readings (nothing answered within the hypothesis' range limit) as sound that
  // passed everything nearer than the hypothesis: an echo from beyond the limit ...
  bool beyond_limit = true;
  // ... and no echo at all.
  bool silence = true;
  // Such a reading passes a cell only from where the cell answered before: the transducer within
  // the beam's half width of the mean direction from the cell to the transducers that heard it. A
  // plane answers only a transducer near its normal, so silence from elsewhere is what a pane gives
  // (a pane heard sparsely is no line to the line test); from there it would have answered.
  bool heard_from_gate = true;
  // ... and empties it only after k silent looks in a row, (1 - p)^k <= silence_risk, p the
  // cell's answer rate (hits over hits and silent looks, this run's too: what it would be if the
  // reflector were still there): a weak reflector that answers now and then (a mesh) needs many,
  // a person or a post that answered every time 2-4. 0: clear_after, as for echoes.
  double silence_risk = 0.05;
  bool unverifiable() const { return beyond_limit || silence; }
  bool enabled() const { return core > 0; }
};
// Reads the `pass_through:` section. Throws ConfigError naming the key path.
PassThroughParams passThroughParams(const Config& c, PassThroughParams base = {});

// The remembered line through a cell, if its neighbourhood is one: the unit normal of the
// principal direction of the neighbourhood's remembered cells (their evidence points).
bool rememberedLineNormal(const AccumulativeGridMap& agm, int ix, int iy, const PassThroughParams& p,
                          geom::Vec2& normal);

// The silent looks in a row after which a cell that answered `hits` times and was silent
// `silent` times is taken to be gone: the least k with (1 - p)^k <= risk, p = hits / (hits +
// silent) (at least one hit counted), at most 1000.
int silentLooksNeeded(int hits, int silent, double risk);

class PassThrough {
 public:
  explicit PassThrough(const PassThroughParams& p) : p_(p) {}
  const PassThroughParams& params() const { return p_; }
  // One firing group's soundings against the map: counts a pass for every remembered cell the
  // group's sound went through (once per group), empties those passed clear_after times in a
  // row. Returns how many cells were emptied. Call before the group's own hits go in.
  int apply(const std::vector<Sounding>& group, AccumulativeGridMap& agm);
  // A hit at `point` heard from `from` (the transducer; the scanner for a laser glint), noted
  // before the group's hits go into the map: where each cell was heard from, for the heard-from
  // gate (kept only while unverifiable readings are used). A cell empty before starts afresh.
  void noteHit(const geom::Vec2& point, const geom::Vec2& from, const AccumulativeGridMap& agm);
  bool notesHits() const { return p_.enabled() && p_.unverifiable() && p_.heard_from_gate; }
  // Cells passed at least once and not yet emptied or hit again (for tests and status).
  size_t pending() const { return passes_.size(); }
  // Cells whose heard-from direction is kept (for tests and status).
  size_t noted() const { return heard_.size(); }
  // Of the cells the last apply() emptied, those that silence emptied (the echoes alone would not
  // have yet).
  int emptiedBySilence() const { return emptied_by_silence_; }
  void clear() {
    passes_.clear();
    heard_.clear();
  }

 private:
  struct Passes {
    int64_t last_hit = 0;  // the cell's last increment when counting started
    int n = 0;             // looks by echoes since
    int silent = 0;        // silent looks since
  };
  struct Look {
    int ix = 0, iy = 0;
    bool silent = false;
    bool operator<(const Look& o) const { return std::tie(ix, iy, silent) < std::tie(o.ix, o.iy, o.silent); }
  };
  PassThroughParams p_;
  struct Heard {
    geom::Vec2 sum{0, 0};  // unit vectors from the cell to where it was heard from
    int64_t cycle = -1;    // the map's cycle at the last note
    int hits = 0;          // noted hits
    int silent = 0;        // silent looks that passed the heard-from gate
  };
  bool heardFrom(int64_t gx, int64_t gy, const geom::Vec2& cell, const geom::Vec2& sensor, double half) const;
  // Whether the cell was heard from within `half` of the line normal `n` (either side), by its
  // hits' mean direction; true when that is not known or rests on fewer than two hits (one may be
  // a rough pane's scatter or crosstalk).
  bool heardAtNormal(int64_t gx, int64_t gy, const geom::Vec2& n, double half) const;
  std::map<std::pair<int64_t, int64_t>, Passes> passes_;  // by global cell
  std::map<std::pair<int64_t, int64_t>, Heard> heard_;    // by global cell
  size_t passes_prune_at_ = 4096, heard_prune_at_ = 4096;  // sizes above which forgotten cells are swept
  int emptied_by_silence_ = 0;
  std::vector<Look> cells_;                                // this group's (window cells)
};

}  // namespace lasonic
