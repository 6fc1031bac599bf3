#include "sdcb/io/report/convergence_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "sdcb/io/common/atomic_file.h"

namespace sdcb {
namespace {

std::string Escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string Fmt(const char* format, double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

}  // namespace

std::string ConvergencePlotSvg(const FitStatistics& statistics,
                               const std::string& title) {
  const auto& rounds = statistics.rounds;
  constexpr double kWidth = 640, kHeight = 400;
  constexpr double kLeft = 70, kRight = 20, kTop = 40, kBottom = 60;
  const double plot_w = kWidth - kLeft - kRight,
               plot_h = kHeight - kTop - kBottom;
  double lo = statistics.options.rmse_percent > 0
                  ? statistics.options.rmse_percent
                  : 1e300;
  double hi = lo < 1e300 ? lo : 0;
  for (const auto& r : rounds) {
    if (r.rmse_percent > 0) lo = std::min(lo, r.rmse_percent);
    hi = std::max(hi, r.max_error_percent);
  }
  if (!(lo > 0) || lo >= 1e300) lo = 1e-3;
  if (!(hi > lo)) hi = lo * 10;
  const double log_lo = std::floor(std::log10(lo)),
               log_hi = std::ceil(std::log10(hi));
  const int n = std::max<int>(1, static_cast<int>(rounds.size()) - 1);
  auto x = [&](double round) { return kLeft + plot_w * round / n; };
  auto y = [&](double value) {
    return kTop + plot_h * (log_hi - std::log10(value)) / (log_hi - log_lo);
  };

  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth
      << "\" height=\"" << kHeight
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << "<text x=\"" << kWidth / 2
      << "\" y=\"22\" text-anchor=\"middle\" font-size=\"14\">" << Escape(title)
      << "</text>\n";
  // Grid and axes: one line per decade, one tick per round.
  for (double e = log_lo; e <= log_hi + 1e-9; e += 1) {
    const double yy = y(std::pow(10.0, e));
    svg << "<line x1=\"" << kLeft << "\" x2=\"" << kLeft + plot_w << "\" y1=\""
        << yy << "\" y2=\"" << yy << "\" stroke=\"#ddd\"/>\n"
        << "<text x=\"" << kLeft - 6 << "\" y=\"" << yy + 4
        << "\" text-anchor=\"end\">" << Fmt("%g", std::pow(10.0, e))
        << "%</text>\n";
  }
  for (size_t i = 0; i < rounds.size(); ++i) {
    svg << "<text x=\"" << x(static_cast<double>(i)) << "\" y=\""
        << kTop + plot_h + 18 << "\" text-anchor=\"middle\">" << rounds[i].round
        << "</text>\n"
        << "<text x=\"" << x(static_cast<double>(i)) << "\" y=\""
        << kTop + plot_h + 32
        << "\" text-anchor=\"middle\" font-size=\"10\" fill=\"#555\">"
        << rounds[i].control_points << "</text>\n";
  }
  svg << "<rect x=\"" << kLeft << "\" y=\"" << kTop << "\" width=\"" << plot_w
      << "\" height=\"" << plot_h << "\" fill=\"none\" stroke=\"black\"/>\n"
      << "<text x=\"" << kLeft + plot_w / 2 << "\" y=\"" << kHeight - 10
      << "\" text-anchor=\"middle\">round (control points below)</text>\n"
      << "<text transform=\"translate(16," << kTop + plot_h / 2
      << ") rotate(-90)\" text-anchor=\"middle\">error (% of largest side, "
         "log)</text>\n";
  if (statistics.options.rmse_percent > 0) {
    const double yy = y(statistics.options.rmse_percent);
    svg << "<line x1=\"" << kLeft << "\" x2=\"" << kLeft + plot_w << "\" y1=\""
        << yy << "\" y2=\"" << yy
        << "\" stroke=\"#2a2\" stroke-dasharray=\"6 4\"/>\n";
  }
  auto polyline = [&](auto value, const char* color) {
    svg << "<polyline fill=\"none\" stroke=\"" << color
        << "\" stroke-width=\"2\" points=\"";
    for (size_t i = 0; i < rounds.size(); ++i) {
      svg << x(static_cast<double>(i)) << "," << y(value(rounds[i])) << " ";
    }
    svg << "\"/>\n";
    for (size_t i = 0; i < rounds.size(); ++i) {
      svg << "<circle cx=\"" << x(static_cast<double>(i)) << "\" cy=\""
          << y(value(rounds[i])) << "\" r=\"3\" fill=\"" << color << "\"/>\n";
    }
  };
  polyline(
      [](const RoundStatistics& r) { return std::max(r.rmse_percent, 1e-12); },
      "#1f5fbf");
  polyline(
      [](const RoundStatistics& r) {
        return std::max(r.max_error_percent, 1e-12);
      },
      "#c0392b");
  // Legend.
  const double lx = kLeft + plot_w - 190, ly = kTop + 16;
  svg << "<line x1=\"" << lx << "\" x2=\"" << lx + 24 << "\" y1=\"" << ly
      << "\" y2=\"" << ly
      << "\" stroke=\"#1f5fbf\" stroke-width=\"2\"/><text x=\"" << lx + 30
      << "\" y=\"" << ly + 4 << "\">RMSE</text>\n"
      << "<line x1=\"" << lx << "\" x2=\"" << lx + 24 << "\" y1=\"" << ly + 18
      << "\" y2=\"" << ly + 18
      << "\" stroke=\"#c0392b\" stroke-width=\"2\"/><text x=\"" << lx + 30
      << "\" y=\"" << ly + 22 << "\">max error</text>\n"
      << "<line x1=\"" << lx << "\" x2=\"" << lx + 24 << "\" y1=\"" << ly + 36
      << "\" y2=\"" << ly + 36
      << "\" stroke=\"#2a2\" stroke-dasharray=\"6 4\"/><text x=\"" << lx + 30
      << "\" y=\"" << ly + 40 << "\">RMSE target "
      << Fmt("%g", statistics.options.rmse_percent) << "%</text>\n";
  svg << "</svg>\n";
  return svg.str();
}

Status WriteConvergencePlot(const FitStatistics& statistics,
                            const std::string& title, const std::string& path) {
  return WriteFileAtomically(ConvergencePlotSvg(statistics, title), path);
}

}  // namespace sdcb
