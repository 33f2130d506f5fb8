#include "incise/incision/incision.h"

#include "incise/core/format.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "incise/bspline/bspline_curve.h"
#include "incise/bspline/knot_vector.h"
#include "incise/bspline/tensor_kernel.h"

namespace incise::incision {

namespace {

[[noreturn]] void refuse(const std::string& what) { throw std::invalid_argument("Incision: " + what); }

void requirePositive(double value, const char* name) {
  if (!(std::isfinite(value) && value > 0.0))
    refuse(std::string(name) + " = " + core::formatNumber(value) + " must be finite and > 0");
}

void validate(const IncisionOptions& o) {
  requirePositive(o.depth_m, "depth_m");
  requirePositive(o.min_depth_m, "min_depth_m");
  if (o.min_depth_m > o.depth_m)
    refuse("min_depth_m = " + core::formatNumber(o.min_depth_m) +
           " must be <= depth_m = " + core::formatNumber(o.depth_m));
  if (!(std::isfinite(o.opening_m) && o.opening_m >= 0.0))
    refuse("opening_m = " + core::formatNumber(o.opening_m) + " must be finite and >= 0");
  requirePositive(o.alpha_m, "alpha_m");
  requirePositive(o.beta_m, "beta_m");
  requirePositive(o.spacing_m, "spacing_m");
  requirePositive(o.retraction_time_s, "retraction_time_s");
  requirePositive(o.taper_m, "taper_m");
  requirePositive(o.max_step_m, "max_step_m");
  if (!(std::isfinite(o.epsilon) && o.epsilon > 0.0 && o.epsilon < 1e-3))
    refuse("epsilon = " + core::formatNumber(o.epsilon) + " must be in (0, 1e-3)");
  if (o.order < 2 || o.order > bspline::kMaxOrder) refuse("order = " + std::to_string(o.order) + " is outside [2, 16]");
  for (const auto& [count, name] :
       {std::pair{o.across_controls, "across_controls"}, std::pair{o.normal_controls, "normal_controls"}})
    if (count < o.order || count % 2 == 0)
      refuse(std::string(name) + " = " + std::to_string(count) + " must be odd and >= order " +
             std::to_string(o.order));
  if (o.max_columns < 2 * o.order + 2)
    refuse("max_columns = " + std::to_string(o.max_columns) + " must be >= 2 * order + 2");
  const double half_depth_m = (o.normal_controls / 2) * o.beta_m;
  if (o.depth_m > 0.8 * half_depth_m)
    refuse("depth_m = " + core::formatNumber(o.depth_m) +
           " needs more lattice below the surface: (normal_controls / 2) * beta_m = " +
           core::formatNumber(half_depth_m) + " must be >= depth_m / 0.8");
}

bool finite(const StrokeSample& s) { return s.point_m.allFinite() && s.normal.allFinite() && std::isfinite(s.time_s); }

// The paper's quadratic B-spline kernel, scaled to 1 at x = 0 and 0 from x = 1 on.
double quadraticKernel(double x) {
  x = std::abs(x);
  if (x >= 1.0) return 0.0;
  return x <= 0.5 ? 1.0 - 2.0 * x * x : 2.0 * (1.0 - x) * (1.0 - x);
}

// The opening's time response: 0 at x = 0, 1 from x = 1 on, smooth (C^2) in between.
double retraction(double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  const double rest = 1.0 - x;
  return 1.0 - rest * rest * rest;
}

// Eq. (2)'s across offsets floor(l/2) - i after raising u = 1/2 to multiplicity `order` (the same Boehm
// insertion as the lattice's, applied to the offsets as a 1-D curve).
std::vector<double> insertedOffsets(int order, int count, const std::vector<double>& u_knots_before) {
  std::vector<Eigen::Vector3d> offsets(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) offsets[static_cast<size_t>(i)] = Eigen::Vector3d(count / 2 - i, 0.0, 0.0);
  bspline::BSplineCurve curve(order, u_knots_before, std::move(offsets));
  const int times = order - bspline::knotMultiplicity(u_knots_before, 0.5);
  if (times > 0) curve.insertKnot(0.5, times);
  std::vector<double> result;
  for (const auto& c : curve.controls()) result.push_back(c.x());
  return result;
}

}  // namespace

const char* toString(SampleStatus status) noexcept {
  switch (status) {
    case SampleStatus::Accepted:
      return "accepted";
    case SampleStatus::SkippedStill:
      return "skipped: stands still";
    case SampleStatus::SkippedBackward:
      return "skipped: goes back along the stroke";
    case SampleStatus::SkippedTime:
      return "skipped: time not after the previous sample";
    case SampleStatus::SkippedJump:
      return "skipped: too far from the previous sample (off the surface?)";
    case SampleStatus::RefusedNaN:
      return "refused: non-finite value";
    case SampleStatus::RefusedNormal:
      return "refused: zero normal";
    case SampleStatus::Ended:
      return "ended: incision finished or lattice full";
    case SampleStatus::EndedAtCorner:
      return "ended: the stroke turns at a corner (a new incision may begin here)";
  }
  return "unknown";
}

Incision::Layout Incision::layout(const IncisionOptions& options) {
  validate(options);
  const int o = options.order;
  const std::vector<double> u_knots = bspline::clampedUniformKnots(o, options.across_controls);
  Layout layout;
  layout.across_offsets = insertedOffsets(o, options.across_controls, u_knots);
  const int planes = static_cast<int>(layout.across_offsets.size());
  // u knots with 1/2 at full multiplicity; the last plane whose support ends at 1/2 closes the - side.
  layout.u_knots = u_knots;
  for (int t = bspline::knotMultiplicity(u_knots, 0.5); t < o; ++t)
    layout.u_knots.insert(std::upper_bound(layout.u_knots.begin(), layout.u_knots.end(), 0.5), 0.5);
  layout.i_minus =
      static_cast<int>(std::lower_bound(layout.u_knots.begin(), layout.u_knots.end(), 0.5) - layout.u_knots.begin()) -
      1;
  // Kernel: 1 on the two discontinuity planes, 0 on the outermost planes; + on the - side (moves towards +S).
  const int i_minus = layout.i_minus;
  const int reach_minus = i_minus, reach_plus = planes - 2 - i_minus;
  layout.kernel.resize(static_cast<size_t>(planes));
  for (int i = 0; i < planes; ++i)
    layout.kernel[static_cast<size_t>(i)] = i <= i_minus ? quadraticKernel(double(i_minus - i) / reach_minus)
                                                         : -quadraticKernel(double(i - i_minus - 1) / reach_plus);
  // Theorem 1: along u (the -S direction) the planes' order must survive the fully opened kernel.
  for (int i = 0; i + 1 < planes; ++i) {
    if (i == i_minus) continue;  // the two sides of the C^-1 knot never share a support
    const double gap_m =
        (layout.across_offsets[static_cast<size_t>(i)] - layout.across_offsets[static_cast<size_t>(i + 1)]) *
        options.alpha_m;
    const double closing_m =
        (layout.kernel[static_cast<size_t>(i + 1)] - layout.kernel[static_cast<size_t>(i)]) * 0.5 * options.opening_m;
    if (!(gap_m - closing_m > 0.05 * gap_m))
      refuse("opening_m = " + core::formatNumber(options.opening_m) + " folds the lattice between control planes " +
             std::to_string(i) + " and " + std::to_string(i + 1) + " (Theorem 1): raise alpha_m = " +
             core::formatNumber(options.alpha_m) + " or across_controls, or lower opening_m");
  }
  return layout;
}

void Incision::validateOptions(const IncisionOptions& options) { (void)layout(options); }

Incision::Incision(const IncisionOptions& options, const StrokeSample& first, const Eigen::Vector3d& blade_direction)
    : options_(options),
      rest_(bspline::BSplineVolume::identity(Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()),
                                             {2, 2, 2}, {2, 2, 2})),
      displacement_(rest_) {
  Layout lattice = layout(options);
  checkStart(first, blade_direction);
  const int o = options.order;
  const int n = options.normal_controls;
  across_offsets_ = std::move(lattice.across_offsets);
  kernel_ = std::move(lattice.kernel);
  i_minus_ = lattice.i_minus;
  const std::vector<double>& u_cut = lattice.u_knots;
  const int planes = static_cast<int>(across_offsets_.size());

  depth_profile_.resize(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) {
    const double depth_m = std::max(0, k - n / 2) * options.beta_m;
    depth_profile_[static_cast<size_t>(k)] = std::clamp(1.0 - depth_m / options.depth_m, 0.0, 1.0);
  }

  std::vector<double> v_knots(static_cast<size_t>(options.max_columns + o));
  for (size_t q = 0; q < v_knots.size(); ++q) v_knots[q] = static_cast<double>(q);
  const std::vector<double> w_knots = bspline::clampedUniformKnots(o, n);
  std::vector<Eigen::Vector3d> zeros(static_cast<size_t>(planes) * options.max_columns * n, Eigen::Vector3d::Zero());
  rest_ = bspline::BSplineVolume({o, o, o}, {u_cut, v_knots, w_knots}, zeros);
  displacement_ = bspline::BSplineVolume({o, o, o}, {u_cut, v_knots, w_knots}, std::move(zeros));
  column_opening_.assign(static_cast<size_t>(options.max_columns), 0.0);
  frames_.resize(static_cast<size_t>(options.max_columns));
  stations_.reserve(static_cast<size_t>(options.max_columns));  // extend() ends the stroke before more

  // The blade's depth in w: solve sum_k N_k(w) (floor(n/2) - k) beta = -depth by bisection on [1/2, 1].
  double lo = 0.5, hi = 1.0;
  for (int iteration = 0; iteration < 80; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    const int span = bspline::findSpan(w_knots, o, n, mid);
    double basis[bspline::kMaxOrder];
    bspline::basisFunctions(w_knots, o, span, mid, basis);
    double offset = 0.0;
    for (int a = 0; a < o; ++a) offset += basis[a] * (n / 2 - (span - o + 1 + a)) * options.beta_m;
    (offset > -options.depth_m ? lo : hi) = mid;
  }
  bottom_w_ = 0.5 * (lo + hi);
  startAt(first, blade_direction);
}

void Incision::checkStart(const StrokeSample& first, const Eigen::Vector3d& blade_direction) const {
  if (!finite(first) || first.normal.norm() < 1e-12) refuse("the first sample must be finite with a non-zero normal");
  if (!blade_direction.allFinite() || blade_direction.cross(first.normal).norm() < 1e-12 * blade_direction.norm())
    refuse("blade_direction must be finite, non-zero and not parallel to the surface normal");
}

double Incision::sampleDepth(const StrokeSample& sample) const noexcept {
  if (!(sample.depth_m >= 0.0)) return options_.depth_m;  // none given (or NaN)
  return std::clamp(sample.depth_m, options_.min_depth_m, options_.depth_m);
}

void Incision::startAt(const StrokeSample& first, const Eigen::Vector3d& blade_direction) {
  blade_direction_ = blade_direction.normalized();
  last_sample_ = first;
  smoothed_ = first;
  smoothed_.normal = first.normal.normalized();
  smoothed_.depth_m = sampleDepth(first);
  path_ = smoothed_;
  path_length_m_ = 0.0;
  addStation(
      {first.point_m, first.normal.normalized(), first.time_s, sampleDepth(first), first.through, first.in_wound});
  to_next_station_m_ = options_.spacing_m;
}

void Incision::restart(const StrokeSample& first, const Eigen::Vector3d& blade_direction) {
  checkStart(first, blade_direction);
  rest_.fillControls(Eigen::Vector3d::Zero());
  displacement_.fillControls(Eigen::Vector3d::Zero());
  std::fill(column_opening_.begin(), column_opening_.end(), 0.0);
  std::fill(frames_.begin(), frames_.end(), Frame{});
  stations_.clear();
  first_unsettled_ = 0;
  finished_ = false;
  row_limited_stations_ = 0;
  startAt(first, blade_direction);
}

SampleStatus Incision::extend(const StrokeSample& sample) noexcept {
  if (finished_) return SampleStatus::Ended;
  if (!finite(sample)) return SampleStatus::RefusedNaN;
  if (sample.normal.norm() < 1e-12) return SampleStatus::RefusedNormal;
  if (!(sample.time_s > last_sample_.time_s)) return SampleStatus::SkippedTime;
  const Eigen::Vector3d step = sample.point_m - last_sample_.point_m;
  const double length_m = step.norm();
  if (length_m < 1e-9) return SampleStatus::SkippedStill;
  if (length_m > options_.max_step_m) return SampleStatus::SkippedJump;
  // Backward against the stroke's overall direction of travel (not the last step's, which dips and climbs
  // with the surface, e.g. across an earlier groove).
  const Eigen::Vector3d travel =
      stations_.size() >= 3 ? Eigen::Vector3d(stations_.back().point - stations_.front().point) : blade_direction_;
  if (step.dot(travel.normalized()) < -0.5 * length_m) return SampleStatus::SkippedBackward;
  if (step.normalized().cross(sample.normal.normalized()).norm() < 1e-6) return SampleStatus::RefusedNormal;

  const double a = 1.0 - std::exp(-length_m / (kSmoothSpacings * options_.spacing_m));
  const Eigen::Vector3d n = sample.normal.normalized();
  StrokeSample& f = smoothed_;
  f.point_m += a * (sample.point_m - f.point_m);
  f.normal += a * (n - f.normal);
  f.normal = f.normal.norm() > 1e-12 ? Eigen::Vector3d(f.normal.normalized()) : n;
  f.time_s += a * (sample.time_s - f.time_s);
  f.depth_m += a * (sampleDepth(sample) - f.depth_m);
  f.through = sample.through, f.in_wound = sample.in_wound;
  StrokeSample to = f;
  to.point_m += 0.5 * n.dot(sample.point_m - f.point_m) * n;
  const bool exempt = last_sample_.in_wound || sample.in_wound || last_sample_.through || sample.through;
  const SampleStatus laid = layStations(to, true, exempt);
  if (laid == SampleStatus::Accepted) last_sample_ = sample;
  return laid;
}

SampleStatus Incision::layStations(const StrokeSample& to, bool corners, bool exempt) noexcept {
  // Stations every spacing_m of arc length along the smoothed path.
  const StrokeSample& from = path_;
  const Eigen::Vector3d step = to.point_m - from.point_m;
  const double length_m = step.norm();
  double along_m = to_next_station_m_;
  while (along_m <= length_m) {
    const double f = along_m / length_m;
    if (static_cast<int>(stations_.size()) + options_.order >= options_.max_columns) {
      end();
      return SampleStatus::Ended;
    }
    if (corners && turnsAtCorner(from.point_m + f * step, exempt)) {
      end();
      return SampleStatus::EndedAtCorner;
    }
    const Eigen::Vector3d normal = (1.0 - f) * from.normal + f * to.normal;
    addStation({from.point_m + f * step, normal.norm() > 1e-12 ? normal.normalized() : to.normal,
                from.time_s + f * (to.time_s - from.time_s), (1.0 - f) * from.depth_m + f * to.depth_m,
                f < 0.5 ? from.through : to.through, from.in_wound || to.in_wound});
    along_m += options_.spacing_m;
  }
  to_next_station_m_ = along_m - length_m;
  path_length_m_ += length_m;
  path_ = to;
  return SampleStatus::Accepted;
}

void Incision::finish() noexcept {
  if (finished_) return;
  if (!stations_.empty()) {
    StrokeSample last = last_sample_;
    last.normal = last.normal.normalized();
    last.depth_m = sampleDepth(last);
    layStations(last, false, false);
  }
  end();
}

void Incision::end() noexcept {
  if (finished_) return;
  finished_ = true;
  refreshRestColumns(std::max(0, stationCount() - 2) + options_.order - 1);
}

bool Incision::turnsAtCorner(const Eigen::Vector3d& next_point_m, bool next_exempt) const noexcept {
  const int count = stationCount();
  if (next_exempt || count < std::max(3, minOpeningStations())) return false;
  for (int k = count - 3; k < count; ++k)
    if (stations_[static_cast<size_t>(k)].in_wound || stations_[static_cast<size_t>(k)].through) return false;
  const Station& last = stations_[static_cast<size_t>(count - 1)];
  const auto inPlane = [&](const Eigen::Vector3d& t) { return Eigen::Vector3d(t - t.dot(last.normal) * last.normal); };
  const Eigen::Vector3d before = inPlane(last.point - stations_[static_cast<size_t>(count - 3)].point);
  const Eigen::Vector3d at = inPlane(next_point_m - stations_[static_cast<size_t>(count - 2)].point);
  return std::atan2(before.cross(at).norm(), before.dot(at)) > kCornerTurn;
}

Eigen::Vector3d Incision::stationNormal(const Eigen::Vector3d& normal, double depth_m) const noexcept {
  if (stations_.empty()) return normal;
  const Station& previous = stations_.back();
  const Eigen::Vector3d& a = previous.normal;
  const Eigen::Vector3d axis = a.cross(normal);
  const double turn = std::atan2(axis.norm(), a.dot(normal));
  const double reach_m =
      (options_.normal_controls / 2) * options_.beta_m * std::max(depth_m, previous.depth_m) / options_.depth_m;
  const double max_turn = kRowShiftSpacings * options_.spacing_m / reach_m;
  // A turn beyond the limit is followed only as far as keeps the lattice within kMaxNormalLag of the
  // surface's normal (a surface curving faster than the limit: the rows follow it at its own rate), but
  // never so far that neighbouring rows meet within kFoldDepths of the blade's depth (a ridge about as
  // sharp as the blade is deep: its focal point).
  if (turn <= max_turn || axis.norm() < 1e-12) return normal;
  const double fold_turn = options_.spacing_m / (kFoldDepths * std::max(depth_m, previous.depth_m));
  const double step = std::max(max_turn, std::min(turn - kMaxNormalLag, fold_turn));
  return (std::cos(step) * a + std::sin(step) * axis.normalized().cross(a)).normalized();
}

void Incision::addStation(Station station) {
  station.normal = stationNormal(station.normal, station.depth_m);
  if (row_limit_) {
    const double limited_m =
        std::max(options_.min_depth_m, row_limit_->rowDepth(station.point, -station.normal, station.depth_m));
    if (limited_m < station.depth_m) {
      station.depth_m = limited_m;
      ++row_limited_stations_;
    }
  }
  stations_.push_back(station);
  // A new station changes the tangent of the one before it and the extrapolated columns after it; while
  // there are at most two stations, T_0 changes too, and with it the padding before the start.
  refreshRestColumns(stationCount() <= 2 ? 0 : stationCount() - 2 + options_.order - 1);
}

Incision::Frame Incision::columnFrame(int column) const noexcept {
  const int padding = options_.order - 1;
  const int count = stationCount();
  const int s = std::clamp(column - padding, 0, count - 1);
  Eigen::Vector3d t;
  if (count < 2) {
    t = blade_direction_;
  } else if (s == 0) {
    t = stations_[1].point - stations_[0].point;
  } else if (s == count - 1) {
    t = stations_[static_cast<size_t>(s)].point - stations_[static_cast<size_t>(s - 1)].point;
  } else {
    t = stations_[static_cast<size_t>(s + 1)].point - stations_[static_cast<size_t>(s - 1)].point;
  }
  Frame frame;
  const Station& st = stations_[static_cast<size_t>(s)];
  frame.n = st.normal;
  frame.depth_m = st.depth_m;
  frame.t = (t - t.dot(frame.n) * frame.n).normalized();  // tangent in the surface's plane
  frame.s = frame.t.cross(frame.n);
  // Columns beyond the stations continue along the tangent, one spacing each.
  frame.g = st.point + double(column - padding - s) * options_.spacing_m * frame.t;
  return frame;
}

void Incision::setRestColumn(int column) {
  const Frame f = columnFrame(column);
  frames_[static_cast<size_t>(column)] = f;
  const int n = options_.normal_controls;
  // Eq. (2)'s rows along the normal scaled with the column's depth: the blade's depth is always at w =
  // bottomW(), so the floor follows the tip column by column (and the walls reach it).
  const double beta_m = options_.beta_m * f.depth_m / options_.depth_m;
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < static_cast<int>(across_offsets_.size()); ++i)
      rest_.setControl(
          i, column, k,
          f.g + across_offsets_[static_cast<size_t>(i)] * options_.alpha_m * f.s + double(n / 2 - k) * beta_m * f.n);
}

int Incision::extrapolatedEnd() const noexcept {
  // The columns after the last station that shape the lattice up to its end: `order` of them suffice.
  return std::min(options_.max_columns, (options_.order - 1) + stationCount() + options_.order);
}

void Incision::refreshRestColumns(int first_column) {
  for (int j = std::max(0, first_column); j < extrapolatedEnd(); ++j) setRestColumn(j);
}

int Incision::finalColumns() const noexcept {
  // A stroke of fewer stations never opens (stationRamp is 0 at every one): cut, it would leave a slit whose
  // walls lie on each other. So nothing is final until it has them; a finished one without them is not cut.
  if (stationCount() < minOpeningStations()) return 0;
  if (finished_) return extrapolatedEnd();
  const int padding = options_.order - 1;
  return stationCount() >= 2 ? padding + stationCount() - 1 : 0;
}

double Incision::finalEndV() const noexcept { return static_cast<double>(finalColumns()); }

double Incision::startV() const noexcept { return (options_.order - 1) + 0.5 * options_.order; }

bool Incision::throughAt(double v) const noexcept {
  if (stations_.empty() || !std::isfinite(v)) return false;
  const double s = std::clamp(std::round(v - startV()), 0.0, static_cast<double>(stationCount() - 1));
  return stations_[static_cast<size_t>(s)].through;
}

double Incision::lastStationV() const noexcept { return startV() + (stationCount() - 1); }

// The stations at each end of the cut whose columns' support reaches beyond it open not at all, the next
// `order` ramp up: so D is 0 on both sides of u = 1/2 beyond the cut (no face the cut does not split is
// torn) and the wound closes towards its ends. Beyond the cut means before startV() and, while the stroke
// goes on, from finalEndV() (the last `order` final stations wait: the wound opens that far behind the
// blade), once finished from lastStationV(). A station's ramp only grows as stations are added.
double Incision::stationRamp(int station, bool settled_end) const noexcept {
  const int o = options_.order, closed = closedEndStations();
  const int last_open = stationCount() - 1 - (finished_ || settled_end ? closed : o);
  // Over taper_m the opening rises as a smoothstep: its curvature along the cut is what a face beside the
  // seam must withstand without folding (a long, gentle taper keeps it small).
  const double stations = std::max(1.0, std::ceil(options_.taper_m / options_.spacing_m));
  const double x = std::clamp(std::min(station - closed + 1, last_open - station + 1) / stations, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

double Incision::stationOpening(int station, double t_s) const noexcept {
  return 0.5 * options_.opening_m * stationRamp(station, false) *
         retraction((t_s - stations_[static_cast<size_t>(station)].time_s) / options_.retraction_time_s);
}

void Incision::setDisplacementColumn(int column, double opening_m) {
  const Frame& f = frames_[static_cast<size_t>(column)];
  for (int k = 0; k < options_.normal_controls; ++k)
    for (int i = 0; i < static_cast<int>(kernel_.size()); ++i)
      displacement_.setControl(
          i, column, k, (kernel_[static_cast<size_t>(i)] * opening_m * depth_profile_[static_cast<size_t>(k)]) * f.s);
  column_opening_[static_cast<size_t>(column)] = opening_m;
}

void Incision::updateOpening(double t_s, std::vector<int>& changed_columns) {
  const int padding = options_.order - 1;
  // Stations whose columns are final: all but the newest (its tangent is not known yet) until finished.
  const int final_stations = finished_ ? stationCount() : std::max(0, stationCount() - 1);
  for (int s = first_unsettled_; s < final_stations; ++s) {
    const int column = s + padding;
    const double opening_m = stationOpening(s, t_s);
    if (opening_m != column_opening_[static_cast<size_t>(column)]) {
      setDisplacementColumn(column, opening_m);
      changed_columns.push_back(column);
    }
    // Station times do not decrease and ramps grow towards the start: once one has settled (its time
    // response done, its ramp as it will stay), every one before it has.
    if (s == first_unsettled_ && t_s - stations_[static_cast<size_t>(s)].time_s >= options_.retraction_time_s &&
        stationRamp(s, false) == stationRamp(s, true))
      ++first_unsettled_;
  }
}

Eigen::AlignedBox3d Incision::columnBox(int column) const noexcept {
  Eigen::AlignedBox3d box;
  const int first = std::max(0, column - options_.order + 1);
  const int last = std::min(column, options_.max_columns - 1);
  for (int j = first; j <= last; ++j)
    for (int k = 0; k < options_.normal_controls; ++k)
      for (int i = 0; i < static_cast<int>(across_offsets_.size()); ++i) box.extend(rest_.control(i, j, k));
  return box;
}

Eigen::Vector3d Incision::inversionGuess(const Eigen::Vector3d& x, int column) const noexcept {
  // Nearest of the columns that shape the slab [column, column + 1), then Eq. (2) read backwards.
  int best = column;
  double best_d2 = INFINITY;
  for (int j = std::max(0, column - options_.order + 1); j <= std::min(column, options_.max_columns - 1); ++j) {
    const double d2 = (frames_[static_cast<size_t>(j)].g - x).squaredNorm();
    if (d2 < best_d2) best_d2 = d2, best = j;
  }
  const Frame& f = frames_[static_cast<size_t>(best)];
  const double half_width_m = (options_.across_controls / 2) * options_.alpha_m;
  const double half_height_m = (options_.normal_controls / 2) * options_.beta_m;
  const double u = 0.5 - 0.5 * (x - f.g).dot(f.s) / half_width_m;
  const double w = 0.5 - 0.5 * (x - f.g).dot(f.n) / half_height_m;
  const double v = best + 0.5 * options_.order + (x - f.g).dot(f.t) / options_.spacing_m;
  const auto dv = rest_.domain(1);
  return {std::clamp(u, 0.0, 1.0), std::clamp(v, dv[0], dv[1]), std::clamp(w, 0.0, 1.0)};
}

int Incision::stencil(const Eigen::Vector3d& uvw, int side, int* first, double* basis) const noexcept {
  const double eps = options_.epsilon;
  double u[2];
  int count = 1;
  switch (side) {
    case -1:
      u[0] = std::min(uvw[0], 0.5 - eps);
      break;
    case 1:
      u[0] = std::max(uvw[0], 0.5);
      break;
    case 2:
      u[0] = 0.5 - eps;
      u[1] = 0.5;
      count = 2;
      break;
    default:
      u[0] = uvw[0];
      break;
  }
  const bspline::BSplineVolume& d = displacement_;
  const int o = options_.order;
  for (int c = 0; c < count; ++c) {
    const double t[3] = {u[c], uvw[1], uvw[2]};
    int corner[3];
    for (int a = 0; a < 3; ++a) {
      const auto domain = d.domain(a);
      const double clamped = std::clamp(std::isnan(t[a]) ? domain[0] : t[a], domain[0], domain[1]);
      const int span = bspline::findSpan(d.knots(a), o, d.controlCounts()[a], clamped);
      bspline::basisFunctions(d.knots(a), o, span, clamped, basis + c * stencilSize() + a * o);
      corner[a] = span - (o - 1);
    }
    first[c] = d.controlIndex(corner[0], corner[1], corner[2]);
  }
  return count;
}

Eigen::Vector3d Incision::displacementFromStencil(const bspline::BSplineVolume& d, int count, const int* first,
                                                  const double* basis) const noexcept {
  const std::array<int, 3> orders = d.orders();
  const int o = options_.order;
  const double* xyz = d.controls().data()->data();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int c = 0; c < count; ++c) {
    const double* b = basis + c * stencilSize();
    sum += bspline::detail::tensorSum(xyz, d.controlCounts()[0], d.controlCounts()[1], first[c], orders, b, b + o,
                                      b + 2 * o);
  }
  return count == 2 ? Eigen::Vector3d(0.5 * sum) : sum;
}

Eigen::Vector3d Incision::displacementAt(const Eigen::Vector3d& uvw, int side) const noexcept {
  int first[2];
  double basis[2 * 3 * bspline::kMaxOrder];
  const int count = stencil(uvw, side, first, basis);
  return displacementFromStencil(count, first, basis);
}

}  // namespace incise::incision
