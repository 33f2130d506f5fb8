// A progress bar on stderr for long work — `replay --fast`, `bench`, `cut`, `wrap` — drawn only when
// stderr is a terminal (never into a log or a pipe), and redrawn only when the shown figure changes, so a
// caller may update it every frame:
//   replay bunny-straight [##########          ]  52%
// Units: `done` and `total` in the caller's own (frames, samples, seconds); done is clamped to [0, total].
// Threads: one thread per bar (the one that updates it). Cost: O(1) per update; a write(2) per redraw.
// Failure: none (a failed write to the terminal is ignored).
#pragma once

#include <string>

namespace incise::apps {

class Progress {
 public:
  Progress(std::string label, double total);
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  ~Progress();  // ends the line if anything was drawn

  void update(double done) noexcept;
  // Draws 100% and ends the line (once).
  void finish() noexcept;

  bool drawing() const noexcept { return enabled_; }

 private:
  void draw(int percent) noexcept;

  std::string label_;
  double total_;
  bool enabled_;
  int shown_percent_ = -1;
  bool finished_ = false;
};

}  // namespace incise::apps
