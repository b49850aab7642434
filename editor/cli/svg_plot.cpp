#include "cli/svg_plot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace plimsoll::cli {

namespace {

constexpr double kWidth = 960, kHeight = 620;
constexpr double kLeft = 90, kTop = 50, kRight = kWidth - 280, kBottom = kHeight - 70;

// Tableau 10: distinguishable in colour and in grey print.
constexpr std::array<const char*, 10> kColours = {"#4e79a7", "#f28e2b", "#e15759", "#76b7b2",
                                                   "#59a14f", "#edc948", "#b07aa1", "#ff9da7",
                                                   "#9c755f", "#bab0ac"};

std::string escape(const std::string& text) {
    std::string out;
    for (char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            default: out += c;
        }
    }
    return out;
}

std::string num(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.1f", v);
    return buffer;
}

bool plottable(double x, double y) {
    return x > 0 && y > 0 && std::isfinite(x) && std::isfinite(y);
}

/// Whole decades [lo, hi] (exponents) around the values; one decade when there is nothing.
struct DecadeRange {
    int lo = 0, hi = 1;

    void widen(double value, bool& any) {
        const int below = static_cast<int>(std::floor(std::log10(value)));
        const int above = static_cast<int>(std::ceil(std::log10(value)));
        lo = any ? std::min(lo, below) : below;
        hi = any ? std::max(hi, above) : above;
        any = true;
    }
    void finish() {
        if (hi <= lo) hi = lo + 1;
    }
    double fraction(double value) const { return (std::log10(value) - lo) / (hi - lo); }
};

std::string decadeLabel(int exponent) {
    return "10<tspan dy=\"-7\" font-size=\"10\">" + std::to_string(exponent) + "</tspan>";
}

}  // namespace

bool writeSvg(const LogLogPlot& plot, std::ostream& out) {
    DecadeRange xs, ys;
    bool anyX = false, anyY = false;
    for (const PlotSeries& s : plot.series) {
        for (const PlotPoint& p : s.points) {
            if (!plottable(p.x, p.y)) continue;
            xs.widen(p.x, anyX);
            ys.widen(p.y, anyY);
        }
    }
    for (const PlotMarker& m : plot.markers)
        if (plottable(m.x, 1.0)) xs.widen(m.x, anyX);
    xs.finish();
    ys.finish();
    auto px = [&](double x) { return kLeft + xs.fraction(x) * (kRight - kLeft); };
    auto py = [&](double y) { return kBottom - ys.fraction(y) * (kBottom - kTop); };

    out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\""
        << kHeight << "\" viewBox=\"0 0 " << kWidth << ' ' << kHeight
        << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
        << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
        << "<text x=\"" << num((kLeft + kRight) / 2) << "\" y=\"28\" text-anchor=\"middle\" "
        << "font-size=\"15\">" << escape(plot.title) << "</text>\n";

    // Grid: a solid line per decade, faint lines at 2..9 times it.
    out << "<g stroke-width=\"1\">\n";
    for (int e = xs.lo; e <= xs.hi; ++e) {
        for (int k = 1; k <= (e < xs.hi ? 9 : 1); ++k) {
            const double x = px(k * std::pow(10.0, e));
            out << "<line x1=\"" << num(x) << "\" y1=\"" << kTop << "\" x2=\"" << num(x)
                << "\" y2=\"" << kBottom << "\" stroke=\"" << (k == 1 ? "#bbb" : "#eee")
                << "\"/>\n";
        }
        out << "<text x=\"" << num(px(std::pow(10.0, e))) << "\" y=\"" << kBottom + 20
            << "\" text-anchor=\"middle\" stroke=\"none\">" << decadeLabel(e) << "</text>\n";
    }
    for (int e = ys.lo; e <= ys.hi; ++e) {
        for (int k = 1; k <= (e < ys.hi ? 9 : 1); ++k) {
            const double y = py(k * std::pow(10.0, e));
            out << "<line x1=\"" << kLeft << "\" y1=\"" << num(y) << "\" x2=\"" << kRight
                << "\" y2=\"" << num(y) << "\" stroke=\"" << (k == 1 ? "#bbb" : "#eee")
                << "\"/>\n";
        }
        out << "<text x=\"" << kLeft - 8 << "\" y=\"" << num(py(std::pow(10.0, e)) + 4)
            << "\" text-anchor=\"end\" stroke=\"none\">" << decadeLabel(e) << "</text>\n";
    }
    out << "</g>\n"
        << "<rect x=\"" << kLeft << "\" y=\"" << kTop << "\" width=\"" << kRight - kLeft
        << "\" height=\"" << kBottom - kTop << "\" fill=\"none\" stroke=\"#333\"/>\n"
        << "<text x=\"" << num((kLeft + kRight) / 2) << "\" y=\"" << kHeight - 22
        << "\" text-anchor=\"middle\">" << escape(plot.xLabel) << "</text>\n"
        << "<text transform=\"translate(24 " << num((kTop + kBottom) / 2)
        << ") rotate(-90)\" text-anchor=\"middle\">" << escape(plot.yLabel) << "</text>\n";

    for (const PlotMarker& m : plot.markers) {
        if (!plottable(m.x, 1.0)) continue;
        const double x = px(m.x);
        out << "<line x1=\"" << num(x) << "\" y1=\"" << kTop << "\" x2=\"" << num(x)
            << "\" y2=\"" << kBottom << "\" stroke=\"#555\" stroke-dasharray=\"6 4\"/>\n"
            << "<text transform=\"translate(" << num(x - 4) << ' ' << kTop + 6
            << ") rotate(-90)\" text-anchor=\"end\" font-size=\"11\" fill=\"#555\">"
            << escape(m.label) << "</text>\n";
    }

    double legendY = kTop + 10;
    for (std::size_t i = 0; i < plot.series.size(); ++i) {
        const PlotSeries& s = plot.series[i];
        const char* colour = kColours[i % kColours.size()];
        std::string path;
        for (const PlotPoint& p : s.points) {
            if (!plottable(p.x, p.y)) continue;
            path += (path.empty() ? "" : " ") + num(px(p.x)) + "," + num(py(p.y));
        }
        out << "<g stroke=\"" << colour << "\" fill=\"" << colour << "\">\n"
            << "<polyline points=\"" << path << "\" fill=\"none\" stroke-width=\"1.8\"/>\n";
        for (const PlotPoint& p : s.points) {
            if (!plottable(p.x, p.y)) continue;
            out << "<circle cx=\"" << num(px(p.x)) << "\" cy=\"" << num(py(p.y))
                << "\" r=\"3.5\"/>\n"
                << "<text x=\"" << num(px(p.x) + 5) << "\" y=\"" << num(py(p.y) - 5)
                << "\" stroke=\"none\" font-size=\"10\">" << escape(p.label) << "</text>\n";
        }
        out << "<line x1=\"" << kRight + 16 << "\" y1=\"" << legendY << "\" x2=\""
            << kRight + 40 << "\" y2=\"" << legendY << "\" stroke-width=\"2\"/>\n"
            << "<text x=\"" << kRight + 46 << "\" y=\"" << legendY + 4 << "\" stroke=\"none\" "
            << "fill=\"#222\">" << escape(s.name) << "</text>\n"
            << "</g>\n";
        legendY += 20;
    }
    out << "</svg>\n";
    return static_cast<bool>(out);
}

}  // namespace plimsoll::cli
