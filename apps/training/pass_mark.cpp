#include "pass_mark.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "incise/jobs/score_traces.h"
#include "incise/sim/score.h"

namespace incise::apps::training {

namespace {

PassMark parsePassMark(const std::string& text) {
  const auto bad = [&](const std::string& why) {
    return std::invalid_argument("--pass-mark '" + text + "': " + why +
                                 " (expected KEY>=VALUE or KEY<=VALUE, e.g. plan.share_uncut<=0.2)");
  };
  std::size_t op = text.find(">=");
  PassMark mark;
  mark.text = text;
  if (op == std::string::npos) {
    op = text.find("<=");
    mark.at_least = false;
  }
  if (op == std::string::npos) throw bad("no >= or <=");
  mark.key = text.substr(0, op);
  if (mark.key.empty()) throw bad("no key");
  const std::string number = text.substr(op + 2);
  std::size_t used = 0;
  try {
    mark.value = std::stod(number, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (number.empty() || used != number.size() || !std::isfinite(mark.value))
    throw bad("'" + number + "' is not a number");
  return mark;
}

// The value at a dotted path in the line, or nullptr when there is none.
const nlohmann::ordered_json* figure(const nlohmann::ordered_json& line, const std::string& key) {
  const nlohmann::ordered_json* at = &line;
  std::size_t from = 0;
  while (true) {
    const std::size_t dot = key.find('.', from);
    const std::string part = key.substr(from, dot == std::string::npos ? std::string::npos : dot - from);
    if (!at->is_object() || !at->contains(part)) return nullptr;
    at = &(*at)[part];
    if (dot == std::string::npos) return at;
    from = dot + 1;
  }
}

std::string text(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", x);
  return buffer;
}

}  // namespace

std::vector<PassMark> parsePassMarks(const std::vector<std::string>& texts) {
  std::vector<PassMark> marks;
  for (const std::string& t : texts) marks.push_back(parsePassMark(t));
  return marks;
}

void checkPassMarkKeys(const std::vector<PassMark>& marks, const sim::Scenario& scenario) {
  if (marks.empty()) return;
  sim::Score empty;
  empty.has_plan = scenario.plan.given;
  const auto line = nlohmann::ordered_json::parse(jobs::scoreLine("", empty));
  for (const PassMark& m : marks) {
    const nlohmann::ordered_json* at = figure(line, m.key);
    if (at && (at->is_number() || at->is_null())) continue;
    std::string why = "the score has no figure '" + m.key + "'";
    if (m.key.rfind("plan.", 0) == 0 && !scenario.plan.given)
      why = scenario.file.string() + " has no plan, so the score has no '" + m.key + "'";
    else if (at)
      why = "'" + m.key + "' is not a number in the score";
    throw std::invalid_argument("--pass-mark '" + m.text + "': " + why + " (docs/training.md lists the figures)");
  }
}

std::vector<std::string> missedPassMarks(const std::vector<PassMark>& marks, const nlohmann::ordered_json& line) {
  std::vector<std::string> missed;
  for (const PassMark& m : marks) {
    const nlohmann::ordered_json* at = figure(line, m.key);
    const std::string mark = std::string(m.at_least ? ">= " : "<= ") + text(m.value);
    if (!at || !at->is_number()) {
      missed.push_back(m.key + " could not be measured for this session, so it misses the pass mark " + mark);
      continue;
    }
    const double x = at->get<double>();
    if (m.at_least ? x >= m.value : x <= m.value) continue;
    missed.push_back(m.key + " is " + text(x) + ", " + (m.at_least ? "below" : "above") + " the pass mark " + mark);
  }
  return missed;
}

}  // namespace incise::apps::training
