#include "progress.h"

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace incise::apps {

namespace {
constexpr int kWidth = 40;
}

Progress::Progress(std::string label, double total)
    : label_(std::move(label)), total_(total > 0.0 ? total : 1.0), enabled_(isatty(STDERR_FILENO) == 1) {}

Progress::~Progress() { finish(); }

void Progress::update(double done) noexcept {
  if (!enabled_ || finished_) return;
  const double fraction = std::clamp(std::isfinite(done) ? done / total_ : 0.0, 0.0, 1.0);
  const int percent = static_cast<int>(std::floor(fraction * 100.0));
  if (percent != shown_percent_) draw(percent);
}

void Progress::finish() noexcept {
  if (!enabled_ || finished_) return;
  finished_ = true;
  if (shown_percent_ < 0) return;  // nothing drawn: no line to end
  draw(100);
  (void)!write(STDERR_FILENO, "\n", 1);
}

void Progress::draw(int percent) noexcept {
  shown_percent_ = percent;
  char bar[kWidth + 1];
  const int filled = kWidth * percent / 100;
  for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : ' ';
  bar[kWidth] = '\0';
  char line[512];
  const int n = std::snprintf(line, sizeof line, "\r%s [%s] %3d%%", label_.c_str(), bar, percent);
  if (n > 0) (void)!write(STDERR_FILENO, line, static_cast<std::size_t>(std::min<int>(n, sizeof line - 1)));
}

}  // namespace incise::apps
