#include "observe/analysis.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sphib {

int Series::column(const std::string& name) const {
  const auto it = std::find(columns.begin(), columns.end(), name);
  return it == columns.end() ? -1 : static_cast<int>(it - columns.begin());
}

void Observers::add(std::unique_ptr<Analysis> a) {
  for (auto& c : a->columns()) {
    if (series_.column(c) >= 0)
      throw std::invalid_argument("diagnostics column '" + c + "' twice (an observer named like another column): give it "
                                  "another name");
    series_.columns.push_back(std::move(c));
  }
  analyses_.push_back(std::move(a));
}

double Observers::last(const std::string& column) const {
  const int c = series_.column(column);
  return c < 0 || series_.rows.empty() ? NAN : series_.rows.back()[c];
}

void Observers::before_step(const Simulation& sim) {
  for (auto& a : analyses_) a->before_step(sim);
}

void Observers::after_step(const Simulation& sim) {
  for (auto& a : analyses_) a->after_step(sim);
}

const std::vector<double>& Observers::sample(const Simulation& sim) {
  std::vector<double> row;
  row.reserve(series_.columns.size());
  for (auto& a : analyses_) a->sample(sim, row);
  series_.rows.push_back(std::move(row));
  return series_.rows.back();
}

bool Observers::done() const {
  return std::any_of(analyses_.begin(), analyses_.end(), [](const auto& a) { return a->done(); });
}

void Observers::summarize(const Simulation& sim, nlohmann::json& summary) const {
  for (const auto& a : analyses_) a->summarize(sim, series_, summary);
}

nlohmann::json Observers::state() const {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& a : analyses_) j.push_back(a->save());
  return j;
}

void Observers::restore(const nlohmann::json& state, const Series& series) {
  if (series.columns != series_.columns || !state.is_array() || state.size() != analyses_.size())
    throw std::invalid_argument("its diagnostics (columns or analyses) are not those of this scene");
  series_.rows = series.rows;
  for (size_t k = 0; k < analyses_.size(); ++k) analyses_[k]->restore(state[k]);
}

namespace {

class UserObservers final : public Analysis {
 public:
  explicit UserObservers(std::vector<Observer> o) : obs_(std::move(o)) {}
  std::vector<std::string> columns() const override {
    std::vector<std::string> c;
    for (const auto& o : obs_) c.push_back(o.name);
    return c;
  }
  void sample(const Simulation& sim, std::vector<double>& row) override {
    for (const auto& o : obs_) row.push_back(o.value(sim));
  }
  void summarize(const Simulation& sim, const Series&, nlohmann::json& j) const override {
    for (const auto& o : obs_)
      if (!j.contains(o.name)) j[o.name] = o.value(sim);  // never in place of a figure of the run's
  }

 private:
  std::vector<Observer> obs_;
};

}  // namespace

std::unique_ptr<Analysis> user_observers(std::vector<Observer> observers) {
  return std::make_unique<UserObservers>(std::move(observers));
}

}  // namespace sphib
