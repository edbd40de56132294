//! The plots' tests: what each picture holds, and its edge cases.

use super::*;

fn series(name: &str, pts: Vec<(f64, f64)>) -> Series {
    Series { name: name.into(), points: pts }
}

fn plot<'a>(s: &'a [Series]) -> LinePlot<'a> {
    LinePlot { title: "Frame time", x_label: "frame", y_label: "ms", series: s, ..Default::default() }
}

fn decode(f: &Figure) -> image::RgbImage {
    image::load_from_memory(&f.png).unwrap().to_rgb8()
}

fn has_color(img: &image::RgbImage, c: RGBColor) -> bool {
    img.pixels().any(|p| p.0 == [c.0, c.1, c.2])
}

fn check_svg(f: &Figure, texts: &[&str]) {
    let s = f.svg.trim();
    assert!(s.starts_with("<svg"), "{}", &s[..50]);
    assert!(s.ends_with("</svg>"));
    for t in texts {
        assert!(s.contains(t), "svg lacks '{t}'");
    }
}

fn two_series() -> Vec<Series> {
    vec![series("hroc", (0..100).map(|i| (i as f64, 5.0 + (i as f64 * 0.1).sin())).collect()), series("noc", (0..100).map(|i| (i as f64, 20.0 + (i as f64 * 0.1).cos())).collect())]
}

#[test]
fn line_plot_png_and_svg() {
    let s = two_series();
    let f = line_plot(&plot(&s), (640, 400)).unwrap();
    assert_eq!(f.size, (640, 400));
    let img = decode(&f);
    assert_eq!(img.dimensions(), (640, 400));
    assert!(img.pixels().any(|p| p != img.get_pixel(0, 0)), "flat image");
    assert!(has_color(&img, color(0)));
    assert!(has_color(&img, color(1)));
    check_svg(&f, &["Frame time", "hroc", "noc", "frame", "ms"]);
}

#[test]
fn log_log_plot() {
    let s = vec![
        series("hroc", (0..=30).map(|i| (1e3 * 10f64.powf(i as f64 / 10.0), 0.5 + i as f64)).collect()),
        series("vfc", (0..=30).map(|i| (1e3 * 10f64.powf(i as f64 / 10.0), 2.0 * (1.0 + i as f64))).collect()),
    ];
    let f = line_plot(&LinePlot { log_x: true, log_y: true, ..plot(&s) }, (640, 400)).unwrap();
    assert!(has_color(&decode(&f), color(0)));
    check_svg(&f, &["1e6", "hroc", "vfc"]);
}

#[test]
fn log_axis_without_a_power_of_ten_in_the_data() {
    let s = vec![series("a", vec![(2.0, 3.0), (5.0, 7.0)])];
    let f = line_plot(&LinePlot { log_x: true, log_y: true, ..plot(&s) }, (400, 300)).unwrap();
    check_svg(&f, &["<text"]);
}

#[test]
fn single_point_series() {
    let s = vec![series("one", vec![(3.0, 4.0)])];
    let f = line_plot(&plot(&s), (400, 300)).unwrap();
    assert!(has_color(&decode(&f), color(0)));
    let f = line_plot(&LinePlot { log_x: true, log_y: true, ..plot(&s) }, (400, 300)).unwrap();
    assert!(has_color(&decode(&f), color(0)));
    let zero = vec![series("zero", vec![(0.0, 0.0)])];
    line_plot(&plot(&zero), (400, 300)).unwrap();
    // Ranges at the edges of f64's precision and magnitude.
    let close = vec![series("close", vec![(1.0, 1.0), (1.0 + 1e-15, 1.0 + 4e-16)])];
    line_plot(&plot(&close), (400, 300)).unwrap();
    let huge = vec![series("huge", vec![(1e300, -1e300), (2e300, 1e300)])];
    line_plot(&plot(&huge), (400, 300)).unwrap();
}

#[test]
fn non_finite_and_log_domain_points_are_skipped() {
    let s = vec![series("a", vec![(f64::NAN, 1.0), (1.0, f64::INFINITY), (2.0, 3.0), (3.0, -1.0), (4.0, 5.0)])];
    // The finite points (on a log axis, the positive ones) are drawn.
    for f in [line_plot(&plot(&s), (400, 300)).unwrap(), line_plot(&LinePlot { log_y: true, ..plot(&s) }, (400, 300)).unwrap()] {
        assert!(has_color(&decode(&f), color(0)), "the series is not drawn");
        check_svg(&f, &["<text"]);
    }
}

#[test]
fn bad_line_plots_are_errors() {
    let err = |s: &[Series], log: bool| line_plot(&LinePlot { log_x: log, log_y: log, ..plot(s) }, (400, 300)).is_err();
    assert!(err(&[], false), "no series");
    assert!(err(&[series("a", vec![]), series("b", vec![])], false), "all empty");
    assert!(err(&[series("a", vec![(f64::NAN, 1.0), (2.0, f64::INFINITY), (f64::NEG_INFINITY, 0.0)])], false), "nothing finite");
    assert!(err(&[series("a", vec![(0.0, 1.0), (-1.0, 2.0), (3.0, 0.0)])], true), "nothing positive on log axes");
    assert!(err(&[series("a", vec![(1.0, f64::MAX), (2.0, -f64::MAX)])], false), "range overflows");
    let s = two_series();
    assert!(line_plot(&plot(&s), (10, 10)).is_err(), "too small");
    assert!(line_plot(&plot(&s), (100_000, 400)).is_err(), "too large");
}

fn cats() -> Vec<String> {
    vec!["hroc-na".into(), "hroc-cr".into(), "hroc-of".into(), "hroc".into()]
}

fn layers() -> Vec<(String, Vec<f64>)> {
    vec![("draw visible".into(), vec![1.0, 1.2, 0.9, 1.0]), ("find groups".into(), vec![0.3, 0.3, 0.4, 0.35]), ("test groups".into(), vec![0.8, 0.5, 0.7, 0.45])]
}

#[test]
fn stacked_bars_png_and_svg() {
    let (c, l) = (cats(), layers());
    let p = StackedBars { title: "GPU ms per stage", y_label: "ms", categories: &c, layers: &l };
    let f = stacked_bars(&p, (640, 400)).unwrap();
    let img = decode(&f);
    assert_eq!(img.dimensions(), (640, 400));
    for i in 0..l.len() {
        assert!(has_color(&img, color(i)), "layer {i}");
    }
    check_svg(&f, &["GPU ms per stage", "hroc-na", "hroc-of", "draw visible", "find groups", "test groups"]);
}

#[test]
fn stacked_bars_edge_cases() {
    // Many long names (vertical labels), one category, all zero.
    let c: Vec<String> = (0..12).map(|i| format!("a rather long category {i}")).collect();
    let l = vec![("x".to_string(), (0..12).map(|i| i as f64).collect())];
    let f = stacked_bars(&StackedBars { title: "t", y_label: "ms", categories: &c, layers: &l }, (640, 400)).unwrap();
    assert!(has_color(&decode(&f), color(0)), "no bar drawn");
    check_svg(&f, &["a rather long category 0", "a rather long category 11"]);
    let one = vec!["only".to_string()];
    let l = vec![("zero layer".to_string(), vec![0.0]), ("nan layer".to_string(), vec![f64::NAN])];
    let f = stacked_bars(&StackedBars { title: "t", y_label: "ms", categories: &one, layers: &l }, (300, 200)).unwrap();
    assert_eq!(decode(&f).dimensions(), (300, 200));
    check_svg(&f, &["only", "zero layer", "nan layer"]);
}

#[test]
fn bad_stacked_bars_are_errors() {
    let c = cats();
    let bars = |c: &[String], l: &[(String, Vec<f64>)]| stacked_bars(&StackedBars { title: "t", y_label: "ms", categories: c, layers: l }, (400, 300));
    assert!(bars(&[], &[]).is_err(), "no categories");
    assert!(bars(&c, &[]).is_err(), "no layers");
    assert!(bars(&c, &[("a".into(), vec![1.0, 2.0])]).is_err(), "ragged");
    assert!(bars(&c, &[("a".into(), vec![1.0, -2.0, 1.0, 1.0])]).is_err(), "negative");
    assert!(bars(&c, &[("a".into(), vec![f64::NAN, f64::INFINITY, f64::NAN, f64::NAN])]).is_err(), "nothing finite");
    assert!(bars(&c, &[("a".into(), vec![f64::MAX; 4]), ("b".into(), vec![f64::MAX; 4])]).is_err(), "total overflows");
}

#[test]
fn colors_are_distinct() {
    for i in 0..12 {
        for j in 0..i {
            assert_ne!(color(i), color(j), "{i} {j}");
        }
    }
    assert_eq!(color(3), color(3));
}

#[test]
fn number_labels() {
    assert_eq!(number(1000.0, false), "1000");
    assert_eq!(number(0.25, false), "0.25");
    assert_eq!(number(12.5, false), "12.5");
    assert_eq!(number(1e6, true), "1e6");
    assert_eq!(number(2.5e-5, true), "2.5e-5");
    assert_eq!(number(0.0, true), "0");
}

#[test]
fn save_writes_both_files() {
    let s = two_series();
    let f = line_plot(&plot(&s), (400, 300)).unwrap();
    let dir = std::env::temp_dir().join(format!("hroc-plot-test-{}", std::process::id()));
    let (svg, png) = f.save(&dir, "frame_time").unwrap();
    assert_eq!(svg, dir.join("frame_time.svg"));
    assert_eq!(std::fs::read_to_string(&svg).unwrap(), f.svg);
    assert_eq!(std::fs::read(&png).unwrap(), f.png);
    assert!(f.save(&dir, "../escape").is_err());
    assert!(f.save(&dir, "").is_err());
    std::fs::remove_dir_all(&dir).unwrap();
}
