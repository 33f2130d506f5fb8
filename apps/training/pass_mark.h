// Pass marks on a session's score, as `incise score` and `incise train` take them (--pass-mark, repeatable):
// "KEY>=VALUE" or "KEY<=VALUE", KEY a dotted path into the score's JSON line (sim::scoreJson: `economy`,
// `plan.share_within_lateral_tolerance`, `session.sparc`, ...) naming a number, VALUE a number. A line meets
// a mark when its figure is on the mark's side of VALUE (VALUE itself included); a figure the session could
// not measure (null in the line: NaN) misses every mark on it.
//
// Threads: any. Cost: a key lookup per mark and line. Failure: parsePassMarks and checkPassMarkKeys throw
// std::invalid_argument naming the mark and what is wrong with it (exit 2 in the commands).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "incise/sim/scenario.h"

namespace incise::apps::training {

struct PassMark {
  std::string text;      // as given, e.g. "plan.share_uncut<=0.2"
  std::string key;       // "plan.share_uncut"
  bool at_least = true;  // ">=" (higher passes) or "<=" (lower passes)
  double value = 0.0;
};

// Each "KEY>=VALUE" or "KEY<=VALUE" parsed; a mark without either operator, an empty key or a VALUE that is
// not a finite number is refused.
std::vector<PassMark> parsePassMarks(const std::vector<std::string>& texts);

// Refuses a mark whose KEY names no number in the score line of a session of `scenario` (an unknown key, an
// object or list, or a plan.* key on a scenario without a plan), before any trace is scored.
void checkPassMarkKeys(const std::vector<PassMark>& marks, const sim::Scenario& scenario);

// The marks `line` misses, each as a sentence ("plan.share_uncut is 0.35, above the pass mark <= 0.2");
// empty when it meets them all.
std::vector<std::string> missedPassMarks(const std::vector<PassMark>& marks, const nlohmann::ordered_json& line);

}  // namespace incise::apps::training
