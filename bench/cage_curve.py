#!/usr/bin/env python3
"""Error against cage size from `sdcb cage --json` reports, as an SVG.

usage: cage_curve.py OUT.svg LABEL=REPORT.json [LABEL=REPORT.json ...]

Every round of a report is one point (faces, two-sided limit rms, measured
with 16 points per face, at least 10000, each way); the last
point of each series, marked with a ring, is the returned cage measured at
>= 100K points each way. Log-log axes; dashed lines at 0.1 % and 0.05 %.
"""
import json
import math
import sys

W, H = 760, 460
LEFT, RIGHT, TOP, BOTTOM = 70, 200, 40, 60
COLORS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"]


def main():
    out = sys.argv[1]
    series = []
    for arg in sys.argv[2:]:
        label, path = arg.split("=", 1)
        report = json.load(open(path))
        points = [(r["faces"], r["limit_rmse_percent"]) for r in report["rounds"]]
        final = (report["faces"], report["limit_rmse_percent"])
        series.append((label, points, final))
    xs = [p[0] for _, pts, f in series for p in pts + [f]]
    ys = [p[1] for _, pts, f in series for p in pts + [f]] + [0.05, 0.1]
    x0, x1 = math.log10(min(xs)) - 0.05, math.log10(max(xs)) + 0.05
    y0 = math.floor(math.log10(min(ys)) * 4) / 4
    y1 = math.ceil(math.log10(max(ys)) * 4) / 4

    def px(x):
        return LEFT + (math.log10(x) - x0) / (x1 - x0) * (W - LEFT - RIGHT)

    def py(y):
        return H - BOTTOM - (math.log10(y) - y0) / (y1 - y0) * (H - TOP - BOTTOM)

    svg = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" '
           'font-family="sans-serif" font-size="12">' % (W, H),
           '<rect width="100%" height="100%" fill="white"/>',
           '<text x="%d" y="22" font-size="14">Limit surface vs spline: '
           'two-sided rms against cage faces</text>' % LEFT]
    # Grid: decades and 2, 5 on x; decades and 2, 5 on y.
    for e in range(int(math.floor(x0)), int(math.ceil(x1)) + 1):
        for m in (1, 2, 5):
            v = m * 10 ** e
            if x0 <= math.log10(v) <= x1:
                svg.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#ddd"/>'
                           % (px(v), TOP, px(v), H - BOTTOM))
                svg.append('<text x="%.1f" y="%d" text-anchor="middle">%g</text>'
                           % (px(v), H - BOTTOM + 16, v))
    for e in range(int(math.floor(y0)), int(math.ceil(y1)) + 1):
        for m in (1, 2, 5):
            v = m * 10 ** e
            if y0 <= math.log10(v) <= y1:
                svg.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>'
                           % (LEFT, py(v), W - RIGHT, py(v)))
                svg.append('<text x="%d" y="%.1f" text-anchor="end">%g %%</text>'
                           % (LEFT - 6, py(v) + 4, v))
    for target in (0.1, 0.05):
        svg.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#555" '
                   'stroke-dasharray="5,4"/>' % (LEFT, py(target), W - RIGHT, py(target)))
    svg.append('<rect x="%d" y="%d" width="%d" height="%d" fill="none" stroke="#333"/>'
               % (LEFT, TOP, W - LEFT - RIGHT, H - TOP - BOTTOM))
    svg.append('<text x="%d" y="%d" text-anchor="middle">cage faces</text>'
               % ((LEFT + W - RIGHT) / 2, H - 18))
    svg.append('<text transform="translate(18,%d) rotate(-90)" text-anchor="middle">'
               'rms, %% of the largest side</text>' % ((TOP + H - BOTTOM) / 2))
    for i, (label, points, final) in enumerate(series):
        color = COLORS[i % len(COLORS)]
        path = " ".join("%s%.1f,%.1f" % ("M" if k == 0 else "L", px(x), py(y))
                        for k, (x, y) in enumerate(points))
        svg.append('<path d="%s" fill="none" stroke="%s" stroke-width="1.8"/>'
                   % (path, color))
        for x, y in points:
            svg.append('<circle cx="%.1f" cy="%.1f" r="2.5" fill="%s"/>'
                       % (px(x), py(y), color))
        svg.append('<circle cx="%.1f" cy="%.1f" r="6" fill="none" stroke="%s" '
                   'stroke-width="1.8"/>' % (px(final[0]), py(final[1]), color))
        ly = TOP + 16 + 20 * i
        svg.append('<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="%s" stroke-width="2"/>'
                   % (W - RIGHT + 12, ly - 4, W - RIGHT + 34, ly - 4, color))
        svg.append('<text x="%d" y="%d">%s</text>' % (W - RIGHT + 40, ly, label))
    svg.append("</svg>")
    open(out, "w").write("\n".join(svg) + "\n")


if __name__ == "__main__":
    main()
