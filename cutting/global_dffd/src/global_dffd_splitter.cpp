// DffdSplitter: the split of a moving model kept from frame to frame (§3.2: only what
// changed is split again). See global_dffd.h for the contract and global_dffd_split.cpp for the split it replays.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "global_dffd_internal.h"
#include "incise/global_dffd/global_dffd.h"

namespace incise::global_dffd {

using detail::SplitStep;

struct DffdSplitter::State {
  detail::Soup soup;
  DffdSplit split;
  std::vector<SplitStep> steps;             // the last full split's constructions, in order
  std::vector<std::int8_t> sides, scratch;  // per model vertex and plane (plane fastest): -1, 0 (on it), +1, 2
  std::vector<std::array<int, 3>> faces;    // the triangles the steps were recorded for
  std::vector<double> planes_u, planes_scratch;
  Eigen::AlignedBox3d box;
  bool replayable = false;  // steps, sides, faces, planes and box describe split
  bool kept = false;
};

namespace {

// Where splitAt puts each model vertex relative to each plane, in the planes' order: a vertex within the
// snap distance is put on the plane (0; its x becomes u for the planes after), else -1 or +1 (2 for NaN).
void planeSides(std::span<const Eigen::Vector3d> positions, const std::vector<double>& planes_u, double snap,
                std::vector<std::int8_t>& sides) {
  const size_t n_planes = planes_u.size();
  sides.resize(positions.size() * n_planes);
  for (size_t v = 0; v < positions.size(); ++v) {
    double x = positions[v].x();
    for (size_t i = 0; i < n_planes; ++i) {
      const double u = planes_u[i];
      std::int8_t side = x < u ? -1 : x > u ? 1 : 2;  // 2: NaN, which splitAt takes as on no side
      if (std::abs(x - u) <= snap) {
        side = 0;
        x = u;
      }
      sides[v * n_planes + i] = side;
    }
  }
}

// The split's positions from the model's: the recorded constructions, in order (splitAt's arithmetic).
// False when a quadrilateral's diagonal would now be chosen otherwise (the connectivity changed; x is then
// partly written).
bool replay(std::span<const Eigen::Vector3d> positions, const std::vector<SplitStep>& steps,
            std::vector<Eigen::Vector3d>& x) {
  x.assign(positions.begin(), positions.end());
  for (const SplitStep& step : steps) {
    switch (step.kind) {
      case SplitStep::Kind::Snap:
        x[static_cast<size_t>(step.a)].x() = step.u_m;
        break;
      case SplitStep::Kind::Point:
        x.push_back(detail::splitPoint(x[static_cast<size_t>(step.a)], x[static_cast<size_t>(step.b)], step.u_m));
        break;
      case SplitStep::Kind::Copy: {
        const Eigen::Vector3d copy = x[static_cast<size_t>(step.a)];
        x.push_back(copy);
        break;
      }
      case SplitStep::Kind::Diagonal: {
        const auto at = [&](int v) -> const Eigen::Vector3d& { return x[static_cast<size_t>(v)]; };
        if (detail::quadDiagonalPC(at(step.a), at(step.b), at(step.c), at(step.d)) != step.diagonal_pc) return false;
        break;
      }
    }
  }
  return true;
}

// The triangles the steps were recorded for, byte for byte (memcmp: 7x faster than comparing arrays here).
bool sameFaces(std::span<const std::array<int, 3>> faces, const std::vector<std::array<int, 3>>& recorded) {
  return faces.size() == recorded.size() &&
         (faces.empty() || std::memcmp(faces.data(), recorded.data(), faces.size_bytes()) == 0);
}

void planesOf(const GlobalDffd& dffd, std::vector<double>& planes_u) {
  planes_u.clear();
  for (const DffdObstacle& obstacle : dffd.obstacles()) planes_u.push_back(obstacle.u);
}

}  // namespace

DffdSplitter::DffdSplitter() : state_(std::make_unique<State>()) {}
DffdSplitter::~DffdSplitter() = default;
DffdSplitter::DffdSplitter(DffdSplitter&&) noexcept = default;
DffdSplitter& DffdSplitter::operator=(DffdSplitter&&) noexcept = default;

bool DffdSplitter::keptConnectivity() const noexcept { return state_->kept; }

const DffdSplit& DffdSplitter::split(std::span<const Eigen::Vector3d> positions,
                                     std::span<const std::array<int, 3>> faces, const GlobalDffd& dffd,
                                     Openings openings) {
  State& st = *state_;
  planesOf(dffd, st.planes_scratch);
  planeSides(positions, st.planes_scratch, detail::snapDistance(dffd.box()), st.scratch);
  st.kept = st.replayable && openings == Openings::Leave && st.planes_scratch == st.planes_u &&
            dffd.box().min() == st.box.min() && dffd.box().max() == st.box.max() && st.scratch == st.sides &&
            sameFaces(faces, st.faces);
  if (st.kept) st.kept = replay(positions, st.steps, st.split.rest_m);
  if (st.kept) return st.split;
  st.replayable = false;
  st.steps.clear();
  detail::soupOf(positions, faces, st.soup);
  struct Recording {  // the soup records the constructions for this split only, even if it throws
    detail::Soup& soup;
    ~Recording() { soup.steps = nullptr; }
  } recording{st.soup};
  st.soup.steps = openings == Openings::Leave ? &st.steps : nullptr;
  detail::splitSoup(st.soup, dffd, openings, st.split);
  if (openings == Openings::Leave) {
    std::swap(st.sides, st.scratch);
    st.faces.assign(faces.begin(), faces.end());
    std::swap(st.planes_u, st.planes_scratch);
    st.box = dffd.box();
    st.replayable = true;
  }
  return st.split;
}

}  // namespace incise::global_dffd
