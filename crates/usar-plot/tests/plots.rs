use usar_plot::{Bar, BarChart, GroupedBarChart, LineChart, Series};

fn chart() -> LineChart {
    let pts = |f: fn(f64) -> f64| {
        (0..=20)
            .map(|i| (i as f64 * 60.0, f(i as f64)))
            .collect::<Vec<_>>()
    };
    LineChart {
        title: "Explored relevant area".into(),
        x_label: "time (s)".into(),
        y_label: "area (m²)".into(),
        series: vec![
            Series::with_band("S-MCDM", pts(|t| 80.0 * t), vec![60.0; 21]),
            Series::line("D-MCDM", pts(|t| 50.0 * t)),
        ],
        y_range: None,
    }
}

#[test]
fn line_chart_writes_a_png_with_text_and_an_svg() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("a.png");
    chart().save(&png).unwrap();
    let img = image::open(&png).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (960, 600));
    // The caption row is drawn with the embedded font: some dark pixels near the top centre.
    let dark = (300..660)
        .flat_map(|x| (5..40).map(move |y| (x, y)))
        .filter(|&(x, y)| img.get_pixel(x, y).0[0] < 100)
        .count();
    assert!(dark > 50, "caption text missing ({dark} dark pixels)");
    if let Ok(dir) = std::env::var("USAR_PLOT_SAMPLE_DIR") {
        chart()
            .save(&std::path::Path::new(&dir).join("sample-line.png"))
            .unwrap();
    }
    let svg = dir.path().join("a.svg");
    chart().save(&svg).unwrap();
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("<svg") && text.contains("S-MCDM"));
}

#[test]
fn bar_chart_and_unknown_extension() {
    let dir = tempfile::tempdir().unwrap();
    let bars = BarChart {
        title: "Steps to explore".into(),
        y_label: "steps".into(),
        bars: vec![
            Bar {
                label: "case 1".into(),
                value: 800.0,
                error: 50.0,
            },
            Bar {
                label: "case 2".into(),
                value: 650.0,
                error: 80.0,
            },
        ],
    };
    bars.save(&dir.path().join("b.png")).unwrap();
    // The saved picture: the chart's size, and bars whose coloured areas stand in the ratio of
    // their values (800 : 650; both start at 0), one in each half of the plot.
    let img = image::open(dir.path().join("b.png")).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (960, 600));
    let coloured = |xs: std::ops::Range<u32>| {
        xs.flat_map(|x| (0..600).map(move |y| (x, y)))
            .filter(|&(x, y)| {
                let [r, g, b] = img.get_pixel(x, y).0.map(i32::from);
                (r - g).abs() + (g - b).abs() + (b - r).abs() > 90
            })
            .count() as f64
    };
    let (left, right) = (coloured(0..480), coloured(480..960));
    assert!(left > 10_000.0 && right > 10_000.0, "{left} / {right}");
    let ratio = left / right;
    assert!(
        (ratio - 800.0 / 650.0).abs() < 0.08,
        "bar areas {left} / {right} = {ratio}"
    );
    if let Ok(dir) = std::env::var("USAR_PLOT_SAMPLE_DIR") {
        bars.save(&std::path::Path::new(&dir).join("sample-bar.png"))
            .unwrap();
    }
    let err = bars
        .save(&dir.path().join("b.jpg"))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("b.jpg") && err.contains(".png or .svg"),
        "{err}"
    );
    assert!(!dir.path().join("b.jpg").exists());
}

#[test]
fn grouped_bar_chart_draws_one_bar_per_series_and_group() {
    let dir = tempfile::tempdir().unwrap();
    let chart = GroupedBarChart {
        title: "Scene explored (%)".into(),
        x_label: "participant".into(),
        y_label: "explored (%)".into(),
        groups: (1..=3).map(|k| k.to_string()).collect(),
        series: vec![
            ("teleoperated".into(), vec![60.0, 88.0, 40.0]),
            ("semi-autonomous".into(), vec![100.0, 100.0, 100.0]),
        ],
    };
    let png = dir.path().join("g.png");
    chart.save(&png).unwrap();
    if let Ok(dir) = std::env::var("USAR_PLOT_SAMPLE_DIR") {
        chart
            .save(&std::path::Path::new(&dir).join("sample-grouped.png"))
            .unwrap();
    }

    let img = image::open(&png).unwrap().to_rgb8();
    // Each series' colour fills a bar per group: count the columns of each colour along the
    // row a little above the x axis.
    let y = img.height() - 80;
    let columns = |c: [u8; 3]| {
        (0..img.width())
            .filter(|&x| img.get_pixel(x, y).0 == c)
            .count()
    };
    let first = columns(palette(0));
    let second = columns(palette(1));
    assert!(
        first > 60 && second > 60,
        "bars missing: {first} / {second}"
    );
    let svg = dir.path().join("g.svg");
    chart.save(&svg).unwrap();
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("teleoperated") && text.contains("semi-autonomous"));
    assert!(text.contains("participant"), "axis label missing");
}

fn palette(k: usize) -> [u8; 3] {
    let (r, g, b) = usar_plot::PALETTE[k];
    [r, g, b]
}
