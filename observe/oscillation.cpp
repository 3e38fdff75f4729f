// The oscillating membrane (Section 5.2.2): period and decay of rx(t), from the extrema of the
// m0_rx series. Period = 2 x the mean spacing of successive extrema; amplitudes A_k = |rx_k - rx_eq|
// with rx_eq the mean of the last two extrema; amplitude_decay = A(t + period)/A(t) from a
// least-squares fit of log A_k = a - lambda t_k.
#include <algorithm>
#include <cmath>

#include "observe/analysis.hpp"

namespace sphib {

namespace {

class OscillationFit final : public Analysis {
 public:
  void summarize(const Simulation&, const Series& series, nlohmann::json& j) const override {
    const int ct = series.column("t"), crx = series.column("m0_rx");
    if (series.rows.empty() || ct < 0 || crx < 0) return;
    const auto& rows = series.rows;
    std::vector<double> te, xe;  // times and values of the extrema
    for (size_t k = 1; k + 1 < rows.size(); ++k) {
      const double a = rows[k - 1][crx], b = rows[k][crx], c = rows[k + 1][crx];
      if ((b > a && b >= c) || (b < a && b <= c)) { te.push_back(rows[k][ct]); xe.push_back(b); }
    }
    if (te.size() >= 3) {
      fit(te, xe, j);
    } else {
      j["period"] = nullptr;  // not measurable: monotone or too short
    }
    j["rx_first_minimum"] = nullptr;
    for (size_t k = 0; k < te.size(); ++k) {
      const auto it = std::find_if(rows.begin(), rows.end(), [&](const auto& r) { return r[ct] == te[k]; });
      const size_t i = it - rows.begin();
      if (i > 0 && rows[i - 1][crx] > xe[k]) {  // a minimum
        j["rx_first_minimum"] = xe[k];
        j["t_first_minimum"] = te[k];
        break;
      }
    }
  }

 private:
  static void fit(const std::vector<double>& te, const std::vector<double>& xe, nlohmann::json& j) {
    double gaps = 0;
    for (size_t k = 1; k < te.size(); ++k) gaps += te[k] - te[k - 1];
    const double period = 2.0 * gaps / (te.size() - 1);
    const double rx_eq = 0.5 * (xe[xe.size() - 1] + xe[xe.size() - 2]);
    double st = 0, sa = 0, stt = 0, sta = 0;
    int n = 0;
    for (size_t k = 0; k + 1 < te.size(); ++k) {
      const double A = std::fabs(xe[k] - rx_eq);
      if (A <= 0) continue;
      st += te[k]; sa += std::log(A); stt += te[k] * te[k]; sta += te[k] * std::log(A); ++n;
    }
    j["period"] = period;
    j["extrema"] = te.size();
    if (n >= 2) {
      const double lambda = -(n * sta - st * sa) / (n * stt - st * st);
      j["amplitude_decay_rate"] = lambda;
      j["amplitude_decay"] = std::exp(-lambda * period);
    }
  }
};

}  // namespace

std::unique_ptr<Analysis> oscillation_fit() { return std::make_unique<OscillationFit>(); }

}  // namespace sphib
