//! A plot as inline SVG: axes, labels, and one polyline per series with a
//! marker at each point (a distinct marker shape per series, so the
//! series tell apart printed in black and white).

use super::facts::Plot;
use super::html::escape;

const WIDTH: f64 = 640.0;
const HEIGHT: f64 = 320.0;
/// Room for the axis labels and tick values.
const LEFT: f64 = 70.0;
const RIGHT: f64 = 20.0;
const TOP: f64 = 30.0;
const BOTTOM: f64 = 50.0;

/// The range a set of values spans, widened when it is a single value
/// (a flat line still gets a height).
fn span(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        low = low.min(v);
        high = high.max(v);
    }
    if !low.is_finite() {
        return (0.0, 1.0);
    }
    if high <= low {
        return (low - 1.0, high + 1.0);
    }
    (low, high)
}

/// A number short enough for a tick label.
fn tick(value: f64) -> String {
    let text = format!("{value:.3}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" {
        "0".into()
    } else {
        text.into()
    }
}

/// `plot` as an `<svg>` element. Points that are not finite numbers are
/// left out.
pub fn plot_svg(plot: &Plot) -> String {
    let points = || plot.series.iter().flat_map(|s| s.points.iter());
    let (x0, x1) = span(points().map(|p| p.0));
    let (y0, y1) = span(points().map(|p| p.1));
    let plot_w = WIDTH - LEFT - RIGHT;
    let plot_h = HEIGHT - TOP - BOTTOM;
    let sx = |x: f64| LEFT + (x - x0) / (x1 - x0) * plot_w;
    let sy = |y: f64| TOP + plot_h - (y - y0) / (y1 - y0) * plot_h;
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"plot\" viewBox=\"0 0 {WIDTH} {HEIGHT}\" \
         role=\"img\" aria-label=\"{}\">\n",
        escape(&plot.title)
    );
    svg += &format!("<title>{}</title>\n", escape(&plot.title));
    svg += &format!(
        "<text x=\"{}\" y=\"18\" text-anchor=\"middle\" font-weight=\"bold\">{}</text>\n",
        WIDTH / 2.0,
        escape(&plot.title)
    );
    // The frame and the axis labels.
    svg += &format!(
        "<rect x=\"{LEFT}\" y=\"{TOP}\" width=\"{plot_w}\" height=\"{plot_h}\" fill=\"none\" stroke=\"black\"/>\n"
    );
    svg += &format!(
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n",
        LEFT + plot_w / 2.0,
        HEIGHT - 8.0,
        escape(&plot.x_label)
    );
    svg += &format!(
        "<text x=\"14\" y=\"{}\" text-anchor=\"middle\" transform=\"rotate(-90 14 {})\">{}</text>\n",
        TOP + plot_h / 2.0,
        TOP + plot_h / 2.0,
        escape(&plot.y_label)
    );
    for (value, x) in [(x0, LEFT), (x1, LEFT + plot_w)] {
        svg += &format!(
            "<text x=\"{x}\" y=\"{}\" text-anchor=\"middle\" font-size=\"11\">{}</text>\n",
            TOP + plot_h + 16.0,
            tick(value)
        );
    }
    for (value, y) in [(y0, TOP + plot_h), (y1, TOP)] {
        svg += &format!(
            "<text x=\"{}\" y=\"{}\" text-anchor=\"end\" font-size=\"11\">{}</text>\n",
            LEFT - 4.0,
            y + 4.0,
            tick(value)
        );
    }
    const DASHES: [&str; 4] = ["", "6 3", "2 2", "8 3 2 3"];
    for (index, series) in plot.series.iter().enumerate() {
        let kept: Vec<(f64, f64)> = series
            .points
            .iter()
            .copied()
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .map(|(x, y)| (sx(x), sy(y)))
            .collect();
        let coordinates: Vec<String> = kept.iter().map(|(x, y)| format!("{x:.1},{y:.1}")).collect();
        let dash = DASHES[index % DASHES.len()];
        svg += &format!(
            "<g class=\"series\" data-name=\"{}\">\n<polyline fill=\"none\" stroke=\"black\" \
             stroke-dasharray=\"{dash}\" points=\"{}\"/>\n",
            escape(&series.name),
            coordinates.join(" ")
        );
        for (x, y) in &kept {
            svg += &marker(index, *x, *y);
        }
        svg += "</g>\n";
    }
    svg += "</svg>\n";
    svg
}

/// A marker at a point: circle, square, triangle, cross by series.
fn marker(series: usize, x: f64, y: f64) -> String {
    match series % 4 {
        0 => format!("<circle class=\"point\" cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"2.5\"/>\n"),
        1 => format!(
            "<rect class=\"point\" x=\"{:.1}\" y=\"{:.1}\" width=\"5\" height=\"5\"/>\n",
            x - 2.5,
            y - 2.5
        ),
        2 => format!(
            "<polygon class=\"point\" points=\"{:.1},{:.1} {:.1},{:.1} {:.1},{:.1}\"/>\n",
            x,
            y - 3.0,
            x - 3.0,
            y + 2.5,
            x + 3.0,
            y + 2.5
        ),
        _ => format!(
            "<path class=\"point\" d=\"M{:.1},{:.1}l6,6m0,-6l-6,6\" stroke=\"black\"/>\n",
            x - 3.0,
            y - 3.0
        ),
    }
}
