// One local DFFD incision (Schein & Elber, "Discontinuous Free Form Deformations", §4): the lattice that a
// scalpel stroke grows, without any mesh; SurfaceCutter (surface_cutter.h) applies it to a mesh. The
// stroke's samples become stations every spacing_m, one lattice column each (Eq. (2)); u = 1/2 has
// multiplicity `order`, the potential C^-1 discontinuity; the cut is a displacement lattice D that opens
// over time on either side of it. Only final columns are cut, so the result depends only on the samples,
// never on how they were grouped into calls.
//
// Units: metres, seconds. Shapes: rest() and displacement() have (l + order - m0) x max_columns x n controls
// (m0 = multiplicity of 1/2 in the clamped u knots). Threads: one owner (the sim thread); const members
// from that thread. Cost: extend O(1) per station (a fixed number of columns change); updateOpening
// O(columns still opening); construction O(max_columns * l * n) (allocates: do it at load).
// Failure: the constructor throws std::invalid_argument naming the bad option; extend never throws and
// returns a status (bad samples are skipped or refused; the incision stays valid).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "incise/bspline/bspline_volume.h"

namespace incise::incision {

struct IncisionOptions {
  double depth_m = 0.004;           // the deepest groove (d): samples deeper are cut at this depth, and it is
                                    // the depth of samples that carry none
  double min_depth_m = 0.0002;      // a blade less deep only scratches the skin: no groove (the caller's rule;
                                    // a shallower sample given here is cut this deep)
  double opening_m = 0.002;         // full distance between the lips once the wound has retracted (>= 0; 0: the
                                    // lips touch, for a tissue whose own tension opens the wound)
  double alpha_m = 0.0015;          // paper's alpha: spacing of control planes across the cut (along S)
  double beta_m = 0.002;            // paper's beta: spacing of control rows along the normal
  double spacing_m = 0.0005;        // stroke resampling step: one lattice column per spacing
  double retraction_time_s = 0.05;  // time for the opening to reach its full width
  double taper_m = 0.004;           // from each end of the cut, the length over which the wound opens to
                                    // its full width (a smoothstep; at least one spacing)
  double max_step_m = 0.005;        // a sample farther than this from the previous one is skipped
  int order = 4;                    // B-spline order o in u, v and w
  int across_controls = 5;          // l: control planes across the cut before insertion (odd, >= order)
  int normal_controls = 7;          // n: control rows along the normal (odd, >= order)
  int max_columns = 512;            // lattice capacity: the longest stroke is about max_columns * spacing
  double epsilon = 1e-9;            // parameter offset u = 1/2 -/+ epsilon for the lips (paper §3.2)
};

// One sample of the stroke: where the blade touches the surface, the outward surface normal there, and when.
struct StrokeSample {
  Eigen::Vector3d point_m;
  Eigen::Vector3d normal;
  double time_s = 0.0;
  double depth_m = -1.0;  // the blade tip's depth below point_m along -normal (at rest); < 0: options' depth_m
  bool through = false;   // the tip passed the tissue's far side (the caller's measure: SurfaceCutter's)
  bool in_wound = false;  // the point lies in an earlier incision's wound, where the path dips and climbs
                          // (the caller's measure: SurfaceCutter's); no corner ends the incision there
};

enum class SampleStatus : std::uint8_t {
  Accepted,         // used (it may or may not have completed a station)
  SkippedStill,     // closer than 1e-9 m to the previous sample: nothing to add
  SkippedBackward,  // goes back along the stroke (more than 120 degrees from its direction)
  SkippedTime,      // time not after the previous sample's
  SkippedJump,      // farther than max_step_m from the previous sample: the blade left the surface here (two
                    // in a row: the surface cutter ends the incision, the simulation begins one there)
  RefusedNaN,       // a non-finite coordinate, normal or time
  RefusedNormal,    // a zero normal, or one parallel to the step (no side direction)
  Ended,            // the lattice is full, or the incision is finished: the sample is not used
  EndedAtCorner,    // the stroke turns at a corner sharper than the lattice can follow (Incision::extend):
                    // the incision ended at the corner's station, the sample is not used; the caller may
                    // begin another incision at it
};
const char* toString(SampleStatus status) noexcept;

// How deep a lattice row may reach into the tissue the incision cuts (the surface cutter answers from the
// surface as loaded). A row runs from a station's point inwards along its normal, lagging the surface's
// where it turns fast (Incision::stationNormal); over a sharp edge it can meet the tissue's far side
// sideways, where the thickness straight below the surface's vertices sees tissue enough.
// Threads: called on the incision's owner's thread. Must not allocate or throw.
class RowLimit {
 public:
  virtual ~RowLimit() = default;
  // The depth (m) the row from point_m along the unit `inward` may have: want_m, or less where the tissue
  // along it is thinner.
  virtual double rowDepth(const Eigen::Vector3d& point_m, const Eigen::Vector3d& inward,
                          double want_m) const noexcept = 0;
};

class Incision {
 public:
  // Starts an incision at `first` with the blade travelling along `blade_direction` (used as the tangent
  // until a second station exists). Throws std::invalid_argument for bad options (named, with the value),
  // a non-finite or zero first sample, or options under which the opened kernel would fold the lattice
  // (paper Theorem 1: a plane would pass its neighbour; widen alpha_m or lower opening_m).
  Incision(const IncisionOptions& options, const StrokeSample& first, const Eigen::Vector3d& blade_direction);

  // Starts this object over as a new incision at `first` (the state the constructor gives with the same
  // options), reusing its storage: no allocation, so a cutter keeps one spare incision for the sim thread.
  // Throws std::invalid_argument for a bad first sample or direction, as the constructor does.
  void restart(const StrokeSample& first, const Eigen::Vector3d& blade_direction);
  // Finished, and every station's opening at its final width (retraction_time_s after its time): the
  // displacement no longer changes with time.
  bool woundSettled() const noexcept { return finished_ && first_unsettled_ >= stationCount(); }
  // Every station made from now on has its depth limited by `limit` (nullptr: none), after its normal:
  // the station's rows, and with them the walls and the floor, end where `limit` says. `limit` must
  // outlive the incision's use of it (a restart keeps it).
  void limitRows(const RowLimit* limit) noexcept { row_limit_ = limit; }
  // Stations whose depth `limit` made shallower than their samples asked, since the (re)start.
  int rowLimitedStations() const noexcept { return row_limited_stations_; }
  // The blade's direction of travel it started with (a unit vector), as given to the constructor or restart().
  const Eigen::Vector3d& bladeDirection() const noexcept { return blade_direction_; }

  // The option checks of the constructor alone (load time): throws std::invalid_argument as it does.
  static void validateOptions(const IncisionOptions& options);

  // Adds a sample; returns what was done with it. Never throws. Once the stroke has minOpeningStations()
  // (the wound before a corner can open), a station whose path turns by more than kCornerTurn at the last
  // one (the tangents there and at the one before, each across its two neighbours as the columns' frames
  // take them, in the last station's surface plane), away from earlier wounds (StrokeSample::in_wound:
  // a stroke across a groove dips into it and climbs out, which the lattice follows) and from where the
  // blade goes through the tissue (StrokeSample::through: a through-cut there is one kerf), ends the
  // incision at that station: beyond it the columns' across-lines would cross within the lattice (the walls
  // of its inner side fold over each other, e.g. a stroke down a flank into a crease and up the next one).
  // Returns EndedAtCorner then.
  SampleStatus extend(const StrokeSample& sample) noexcept;
  // No more samples: stations along the rest of the way from the smoothed path to the last sample, then
  // the columns after the last station become final and the cut may reach the last station. Idempotent.
  void finish() noexcept;
  // Length of the smoothed path the stations are laid along, from the first sample (m): the stroke's
  // length without the device's noise.
  double pathLength() const noexcept { return path_length_m_; }
  bool finished() const noexcept { return finished_; }

  // The cut is a displacement lattice `displacement()`, D, with the same knots and control points
  //   dP_ijk = +/- kappa(i) * opening_j * rho(k) * S_j   (+ on the u < 1/2 side, which lies towards +S)
  // kappa: the paper's kernel over the u-planes, a quadratic B-spline profile, 1 on the two discontinuity
  // planes and 0 on the outer planes (which stay put, so D = 0 on the lattice's boundary); rho: 1 at and
  // above the surface, falling linearly to 0 at the blade's depth (the blade's V shape); opening_j: half the
  // wound's width times the time response r((t - t_j) / retraction_time_s), r(x) = 1 - (1 - x)^3 on [0, 1]
  // (the opening grows from 0 to its full width as the tissue retracts, and settles exactly), times a ramp
  // that is 0 for the stations whose columns reach beyond the cut's ends and rises over taper_m (a
  // smoothstep): D is 0 on both sides of u = 1/2 beyond the cut, so no face the cut leaves whole is torn,
  // and the wound closes towards its ends. A deformed point is x + D(u, v, w): F = F0 + D with F0(uvw) = x
  // exactly, so points where D is 0 are never moved by inversion error.
  //
  // Sets the displacement lattice for time t_s (>= every sample's time for a meaningful response) and
  // appends to `changed_columns` the columns whose displacement changed since the previous call.
  // No allocation when `changed_columns` has capacity.
  void updateOpening(double t_s, std::vector<int>& changed_columns);

  // The stroke's samples (hit point, surface normal, time) are resampled at a fixed arc length `spacing_m`
  // into stations G_s with normal N_s (the samples', its turn from station to station limited:
  // stationNormal()), tangent T_s (central differences) and side S_s = T_s x N_s. Station s
  // is lattice column j = s + P (P = order - 1 columns of padding before the start, extrapolated along -T_0;
  // columns after the last station are extrapolated along +T). Control points follow the paper's Eq. (2):
  //   P_ijk = G_j + (floor(l/2) - i) alpha S_j + (floor(n/2) - k) beta_j N_j,   beta_j = beta d_j / depth_m
  // (d_j the blade's depth at station j, from its samples, clamped to [min_depth_m, depth_m]: the rows along
  // the normal follow the hand's depth column by column, so the blade's depth is always at w = bottomW()
  // and the floor slopes as the tip goes deeper or shallower), with clamped uniform knots in u (across the cut, l controls) and w (along the normal, n controls) on
  // [0, 1], and uniform unit-spaced knots in v (one span per column), so that appending a column never
  // changes the basis of the columns before it. Then u = 1/2 is raised to multiplicity `order` (Boehm, §3.1):
  // the two coincident planes i_minus, i_plus = i_minus + 1 are the potential C^-1 discontinuity
  // (Definition 2). The lattice with these control points is `rest()`, F0: the map that parameterises the
  // tissue (F0(u, 1/2, w) follows G; w = 1/2 is the surface, w = bottomW() the blade's depth).
  const bspline::BSplineVolume& rest() const noexcept { return rest_; }
  const bspline::BSplineVolume& displacement() const noexcept { return displacement_; }
  const IncisionOptions& options() const noexcept { return options_; }
  // opening_j of column j as last written into displacement() (0 before it opens; 0 for j out of range):
  // a follower that did not call updateOpening compares it with its own copy to find what moved. O(1).
  double columnOpening(int column) const noexcept {
    return column >= 0 && column < static_cast<int>(column_opening_.size())
               ? column_opening_[static_cast<size_t>(column)]
               : 0.0;
  }

  int stationCount() const noexcept { return static_cast<int>(stations_.size()); }
  // The fewest stations of a finished stroke whose wound opens anywhere: the opening is 0 at the
  // closedEndStations() at each end (their columns reach beyond the cut's ends). 5 for a cubic lattice.
  int minOpeningStations() const noexcept { return 2 * closedEndStations() + 1; }
  // Column j is final once station j - P + 1 exists (its tangent is known) or the stroke is
  // finished, and the stroke has minOpeningStations() (a shorter wound cannot open: cut, it would leave a
  // slit whose walls lie on each other; a stroke finished shorter cuts nothing, and a longer one's first
  // stations are cut when it has them). Only final columns open and only the parameter range they
  // determine, v < finalEndV(), is cut;
  // so the cut trails the newest sample by about (order/2 + 1) * spacing_m, and the result depends only on
  // the samples, never on how they were grouped into calls (growing sample by sample = one call with all).
  // Columns [0, finalColumns()) are final.
  int finalColumns() const noexcept;
  // The parameter range whose F0 is final: v < finalEndV().
  double finalEndV() const noexcept;
  // v of the stroke's first station, and of its last one (the cut's end once finished).
  // Whether the blade went through the tissue at parameter v (the station nearest v: StrokeSample::through).
  bool throughAt(double v) const noexcept;
  double startV() const noexcept;
  double lastStationV() const noexcept;
  // The groove's floor below the newest station (m; the blade's depth there, clamped), 0 before the first.
  double frontDepthM() const noexcept { return stations_.empty() ? 0.0 : stations_.back().depth_m; }
  // w of the surface (1/2) and of the blade's depth below it (the same w at every column: the rows scale
  // with each column's depth).
  double surfaceW() const noexcept { return 0.5; }
  double bottomW() const noexcept { return bottom_w_; }
  // Axis-aligned box holding F0 of the parameter slab v in [j, j + 1) (the convex hull of the controls
  // of columns j - order + 1 .. j). Cost O(order * l * n).
  Eigen::AlignedBox3d columnBox(int column) const noexcept;
  // A start for inverting F0 at x near column `column` (nearest column frame, Eq. 2 read backwards).
  Eigen::Vector3d inversionGuess(const Eigen::Vector3d& x, int column) const noexcept;
  // Displacement of a point with parameters uvw on a side: -1 (u < 1/2, lips at 1/2 - epsilon), +1 (u >= 1/2),
  // 0 (right-hand, as evaluate), 2 (the mean of both sides: the bottom of the cut, where the walls meet).
  Eigen::Vector3d displacementAt(const Eigen::Vector3d& uvw, int side) const noexcept;

  // The same, split in two so that a point's spans and basis values are computed once (when it is bound)
  // and every later re-deformation is one o^3 weighted sum per evaluation (as volume_binding.h):
  // stencil() writes `count` (1, or 2 for side 2) evaluations: first[c], the corner control's linear index,
  // and basis[c * stencilSize() ...], the u, v and w basis values; displacementFromStencil() sums them.
  // displacementAt(uvw, side) == displacementFromStencil(stencil(uvw, side)) bit for bit. noexcept, no
  // allocation; the stencil stays valid for the incision's life (its knots never change).
  int stencilSize() const noexcept { return 3 * options_.order; }
  int stencil(const Eigen::Vector3d& uvw, int side, int* first, double* basis) const noexcept;
  Eigen::Vector3d displacementFromStencil(int count, const int* first, const double* basis) const noexcept {
    return displacementFromStencil(displacement_, count, first, basis);
  }
  // The same sum over another lattice of displacement()'s shape (a follower's delayed copy of it).
  Eigen::Vector3d displacementFromStencil(const bspline::BSplineVolume& lattice, int count, const int* first,
                                          const double* basis) const noexcept;

 private:
  static constexpr double kRowShiftSpacings = 1.0;
  static constexpr double kMaxNormalLag = 0.15;  // radians (8.6 degrees)
  // Neighbouring rows meet no nearer than this many blade depths below the surface: the floor keeps a third
  // of the stations' spacing over a sharp ridge (rows meeting at the floor would leave it no width, and the
  // walls' strips would cross there).
  static constexpr double kFoldDepths = 1.5;
  // The sharpest turn of the path between two stations' frames that one incision follows: 35 degrees, so a
  // kink of more than 70 degrees is a corner (on a pad a kink of 75 degrees left 3 pairs of wall faces
  // crossing, 105 and 120 degrees 66 and 137). The shipped traces turn at most 25 degrees (a 6-DOF
  // device's jitter); the bunny's flank run into a crease, 94.
  static constexpr double kCornerTurn = 0.610865238198015;  // radians
  // A device's noise is not travel: the stations are laid along the samples smoothed over kSmoothSpacings
  // station spacings of travel (an exponential filter in arc length, the same whatever the blade's speed,
  // applied alike to the point, normal, depth and time, so each station keeps the depth and time of where
  // it lies); finish() lays the rest of the way to the last sample. Taken as they came, samples with a
  // 6-DOF device's noise of 0.05 mm at 1 kHz zigzagged: the stations turned 35 degrees and more between
  // neighbours and the lattice tangled (the pad's S-curve failed; at 0.1 mm it ended at 14 false corners).
  // The filter's point lies L^2 k / 2 inside a surface of normal curvature k behind its lag L (the kernel's
  // second moment, 2 L^2): moved halfway back to the newest sample's tangent plane (which lies as far
  // outside) it is on the surface to second order, and the groove's depth is the blade's.
  static constexpr double kSmoothSpacings = 1.0;
  // next_exempt: the next station's samples are in a wound or through the tissue (no corner there).
  bool turnsAtCorner(const Eigen::Vector3d& next_point_m, bool next_exempt) const noexcept;
  // Stations along the smoothed path from path_ to `to` (point, normal, time and depth interpolated; depth
  // already clamped); path_ becomes `to`. Returns Accepted, or how the incision ended (Ended: out of
  // columns; EndedAtCorner, tested where `corners` and not `exempt`).
  SampleStatus layStations(const StrokeSample& to, bool corners, bool exempt) noexcept;
  void end() noexcept;  // finished where it is: no stations to the last sample
  struct Station {
    Eigen::Vector3d point, normal;
    double time_s;
    double depth_m;  // clamped to [min_depth_m, depth_m]
    bool through;    // the nearer sample's StrokeSample::through
    bool in_wound;   // either sample's StrokeSample::in_wound
  };
  struct Frame {  // zero until the column is first written, the same in a new and a restarted incision
    Eigen::Vector3d g = Eigen::Vector3d::Zero(), t = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::Zero(),
                    s = Eigen::Vector3d::Zero();
    double depth_m = 0.0;
  };
  // What the options fix: the u knots with 1/2 at full multiplicity, Eq. (2)'s offsets after the
  // insertion, the kernel per u-plane and the last plane of the u < 1/2 side.
  struct Layout {
    std::vector<double> u_knots, across_offsets, kernel;
    int i_minus = 0;
  };
  static Layout layout(const IncisionOptions& options);

  void checkStart(const StrokeSample& first, const Eigen::Vector3d& blade_direction) const;  // throws
  void startAt(const StrokeSample& first, const Eigen::Vector3d& blade_direction);           // the first station
  double sampleDepth(const StrokeSample& sample) const noexcept;  // its depth_m, or the default, clamped
  void addStation(Station station);                               // its normal limited by stationNormal()
  // A station's normal: the samples' (interpolated), turned from the previous station's by at most
  // kRowShiftSpacings * spacing_m / ((n / 2) beta_j), so the ends of the lattice's rows, (n / 2) beta_j from the
  // surface, move at most one spacing between neighbouring columns; but never more than kMaxNormalLag from
  // the samples' (a surface curving faster is followed at its own rate, that far behind: the floor within
  // 1.1% of the blade's depth, 1 - cos(kMaxNormalLag), on a flat surface), unless that takes a turn over
  // spacing_m / (kFoldDepths d_j): rows a spacing apart turning more meet within kFoldDepths d_j of the
  // surface (a ridge about as sharp as the blade is deep, its focal point), so there the rows lag further
  // behind. A faceted scan's normals jump 5-13 degrees from face to face (the bunny's steep flank, every
  // half millimetre); rows that followed them 6 mm down would swing over a spacing from column to column,
  // and the walls' strips twist and cross each other. Cost O(1).
  Eigen::Vector3d stationNormal(const Eigen::Vector3d& normal, double depth_m) const noexcept;
  Frame columnFrame(int column) const noexcept;
  void setRestColumn(int column);
  void refreshRestColumns(int first_column);
  int extrapolatedEnd() const noexcept;
  // The share of the full opening station `station` may have (0 at the cut's ends, 1 inside); with
  // `settled_end` as it will be once the stroke is finished.
  double stationRamp(int station, bool settled_end) const noexcept;
  int closedEndStations() const noexcept { return (options_.order + 1) / 2; }
  double stationOpening(int station, double t_s) const noexcept;
  void setDisplacementColumn(int column, double opening_m);

  IncisionOptions options_;
  Eigen::Vector3d blade_direction_;
  std::vector<double> across_offsets_;  // c'_i: Eq. (2)'s floor(l/2) - i after the knot insertion
  std::vector<double> kernel_;          // kappa(i) per u-plane, signed: + on the u < 1/2 side
  std::vector<double> depth_profile_;   // rho(k)
  int i_minus_ = 0;                     // last control plane of the u < 1/2 side
  double bottom_w_ = 1.0;
  bspline::BSplineVolume rest_;
  bspline::BSplineVolume displacement_;
  std::vector<Station> stations_;
  StrokeSample last_sample_{};
  StrokeSample smoothed_{};             // the filter's state: the samples smoothed (depth clamped, normal unit)
  StrokeSample path_{};                 // the head of the stations' path: smoothed_ put back on the surface
  double path_length_m_ = 0.0;          // of the smoothed path so far
  double to_next_station_m_ = 0.0;      // arc length still to go along the smoothed path to the next station
  std::vector<double> column_opening_;  // opening_j currently in displacement_
  std::vector<Frame> frames_;           // per column, as last written into rest_
  int first_unsettled_ = 0;             // stations before it have settled to their full opening
  bool finished_ = false;
  const RowLimit* row_limit_ = nullptr;  // limitRows()
  int row_limited_stations_ = 0;
};

}  // namespace incise::incision
