//! `optimize --report FILE`: the report of the computed gait written beside the result, its
//! path checked before any work.

mod common;

use common::crawlopt;

#[test]
fn optimize_writes_the_report_of_its_gait() {
    let dir = tempfile::tempdir().unwrap();
    let html = dir.path().join("gait.html");
    let out = crawlopt(&[
        "optimize",
        "examples/three_blocks_gait.toml",
        "--certify",
        "--report",
        html.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("objective J = 2.6 "), "{stdout}");
    assert!(stdout
        .trim_end()
        .ends_with(&format!("wrote {}", html.display())));
    let page = std::fs::read_to_string(&html).unwrap();
    assert!(page.contains("2.6") && page.contains("<script"));
    // Issue 28: the certificate computed by --certify is in the report (verdict, residual
    // table, adjoint figure); the footer names the command that made it; pieces are numbered
    // as in the text.
    assert!(
        page.contains("<h2 id=\"certificate\">"),
        "no certificate section"
    );
    assert!(page.contains("<b id=\"verdict\">degenerate</b>"));
    assert!(page.contains("<span>necessary conditions</span><b>degenerate</b>"));
    assert!(stdout.contains(
        "necessary conditions (Theorem 2.2; discrete form Theorems 6.1-6.2): degenerate"
    ));
    assert!(page.contains("<table id=\"conditions\">") && page.contains("weak_maximality"));
    assert!(page.contains("<figure id=\"fig-adjoint\">"));
    assert!(page.contains(
        "<code>crawlopt optimize three_blocks_gait.toml --certify --report gait.html</code>"
    ));
    assert!(!page.contains("<code>crawlopt report"));
    assert_eq!(text_pieces(&stdout), html_pieces(&page));
    assert_eq!(text_pieces(&stdout).first(), Some(&0));
    // With --json, stdout is the one JSON document; the line goes to stderr.
    let out = crawlopt(&[
        "optimize",
        "examples/three_blocks_gait.toml",
        "--json",
        "--report",
        html.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!((v["objective"].as_f64().unwrap() - 2.6).abs() < 1e-8);
    assert!(String::from_utf8_lossy(&out.stderr).contains("wrote"));
    // Without --certify: no certificate section, and the footer says so.
    let page = std::fs::read_to_string(&html).unwrap();
    assert!(!page.contains("id=\"certificate\"") && !page.contains("fig-adjoint"));
    assert!(
        page.contains("<code>crawlopt optimize three_blocks_gait.toml --report gait.html</code>")
    );
    // `crawlopt report` of the result file names itself.
    let json = dir.path().join("gait.json");
    std::fs::write(&json, &out.stdout).unwrap();
    let again = dir.path().join("again.html");
    let out = crawlopt(&[
        "report",
        json.to_str().unwrap(),
        "-o",
        again.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0));
    let page = std::fs::read_to_string(&again).unwrap();
    assert!(page.contains("<code>crawlopt report gait.json</code>"));
}

/// The piece numbers of the text of `crawlopt optimize` (lines `  j: t = [..]`).
fn text_pieces(stdout: &str) -> Vec<usize> {
    stdout
        .lines()
        .filter_map(|l| {
            let (j, rest) = l.trim_start().split_once(": t = [")?;
            let _ = rest;
            j.parse().ok()
        })
        .collect()
}

/// The piece numbers of the report's table of pieces (the first cell of each row).
fn html_pieces(page: &str) -> Vec<usize> {
    let start = page
        .find("<table id=\"pieces\">")
        .expect("a table of pieces");
    let table = &page[start..start + page[start..].find("</table>").unwrap()];
    table
        .split("<tr><td>")
        .skip(1)
        .filter_map(|row| row.split("</td>").next()?.parse().ok())
        .collect()
}

#[test]
fn a_directory_as_the_report_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let t = std::time::Instant::now();
    let out = crawlopt(&[
        "optimize",
        "examples/three_blocks_gait.toml",
        "--report",
        dir.path().to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).starts_with("error: "));
    assert!(out.stdout.is_empty());
    // The optimum takes seconds (4 s on the 2-core machine); the refusal comes before it.
    assert!(t.elapsed().as_secs_f64() < 2.0, "{:?}", t.elapsed());
}

/// A P_m answer that took a start says so in its HTML report, as its text does, for a crawler
/// and for a general problem (P): where the start came from and its `J` on the grid, the same
/// words as the text's line.
#[test]
fn a_report_names_the_start_of_a_p_m_answer() {
    let dir = tempfile::tempdir().unwrap();
    for model in [
        "examples/one_link_gait.toml",
        "examples/general_three_blocks.toml",
    ] {
        let start = dir.path().join("start.json");
        let out = crawlopt(&["optimize", model, "--method", "local", "--m", "3", "--json"]);
        assert_eq!(out.status.code(), Some(0), "{model}");
        std::fs::write(&start, &out.stdout).unwrap();
        let html = dir.path().join("r.html");
        let (start, html_path) = (start.to_str().unwrap(), html.to_str().unwrap());
        let out = crawlopt(&[
            "optimize", model, "--method", "discrete", "--m", "3", "--start", start, "--report",
            html_path,
        ]);
        assert_eq!(out.status.code(), Some(0), "{model}");
        let stdout = String::from_utf8_lossy(&out.stdout);
        let line = stdout
            .lines()
            .find(|l| l.starts_with("the MILP started from "))
            .unwrap_or_else(|| panic!("{model}: no start in the text: {stdout}"));
        let page = std::fs::read_to_string(&html).unwrap();
        // The line's words up to its J (the report formats numbers its own way).
        let words = &line["the MILP ".len()..line.find(" (J = ").unwrap() + " (J = ".len()];
        assert!(words.contains("start.json"), "{model}: {line}");
        assert!(page.contains(words), "{model}: the report lacks {words:?}");
        // Without a start, no such words.
        let out = crawlopt(&[
            "optimize", model, "--method", "discrete", "--m", "3", "--report", html_path,
        ]);
        assert_eq!(out.status.code(), Some(0), "{model}");
        let page = std::fs::read_to_string(&html).unwrap();
        assert!(!page.contains("started from"), "{model}");
    }
}
