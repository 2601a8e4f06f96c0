//! `ftwire reproduce --quick`: every experiment runs, the report (`report.md` and
//! `report.html`) sets the paper's tables beside ours, and `--docs` writes the documentation's
//! page. That the report does not depend on how many experiments run at once, nor on the order
//! in which they end, is ftwire-lab's unit test
//! `reproduce::tests::the_report_is_the_same_for_any_number_of_jobs_and_any_order_of_ending`
//! (each experiment is its own seeded process).

mod cli_support;

use std::fs;

use cli_support::{assert_exit, assert_success, ftwire};

#[test]
fn the_quick_report_sets_every_table_beside_the_papers() {
    let dir = std::env::temp_dir().join(format!("ftwire-reproduce-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).expect("creates a temporary folder");
    let docs = dir.join("docs");
    fs::create_dir_all(&docs).expect("creates docs/");
    let (text, html) = {
        let out = dir.join("jobs2");
        let output = ftwire(&[
            "reproduce",
            "--quick",
            "--seed",
            "2",
            "--jobs",
            "2",
            "--out",
            out.to_str().expect("UTF-8"),
            "--docs",
            docs.to_str().expect("UTF-8"),
        ]);
        assert_success(&output, "reproduce --quick");
        let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
        assert!(stderr.contains("expected time"), "{stderr}");
        for id in [
            "calibrate",
            "identify",
            "shape",
            "goal",
            "track",
            "passage",
            "passage_offset",
            "calibrate_real_like",
            "shape_real_like",
        ] {
            assert!(out.join(id).join("summary.json").is_file(), "{id}");
            assert!(out.join(id).join("log.txt").is_file(), "{id}'s log");
        }
        (
            fs::read_to_string(out.join("report.md")).expect("report.md"),
            fs::read_to_string(out.join("report.html")).expect("report.html"),
        )
    };
    // The documentation's page: the same tables, the provenance, every figure it links.
    let page = fs::read_to_string(docs.join("results.md")).expect("docs/results.md");
    assert!(
        page.starts_with("<!-- Written by `ftwire reproduce --docs`"),
        "{page}"
    );
    assert!(
        page.contains("at commit `") && page.contains("threads"),
        "{page}"
    );
    assert!(page.contains("--quick --seed 2 --jobs 2"), "{page}");
    let figures: Vec<&str> = page
        .lines()
        .filter_map(|l| l.strip_prefix("![").and_then(|l| l.split_once("](")))
        .map(|(_, target)| target.trim_end_matches(')'))
        .collect();
    assert!(figures.len() >= 5, "{page}");
    for figure in figures {
        assert!(docs.join(figure).is_file(), "{figure}");
    }
    for table in [
        "## Table I",
        "## Table II",
        "## Table III",
        "## Table IV",
        "## §IV-E",
        "| `offset` | closed loop |",
        "§IV-A",
        "| nitinol-2mm-630 | c1 |",
    ] {
        assert!(text.contains(table), "{table} in the report:\n{text}");
        assert!(page.contains(table), "{table} in docs/results.md");
    }
    // Table II has the real-like column filled: every cell of a wire's row is a number.
    let table_ii = text
        .split("## Table II")
        .nth(1)
        .and_then(|rest| rest.split("\n## ").next())
        .expect("Table II");
    let rows: Vec<&str> = table_ii
        .lines()
        .filter(|l| l.starts_with("| nitinol") || l.starts_with("| cable"))
        .collect();
    assert!(!rows.is_empty(), "{table_ii}");
    for row in rows {
        let cells: Vec<&str> = row.trim_matches('|').split('|').map(str::trim).collect();
        assert_eq!(cells.len(), 5, "{row}");
        assert!(
            cells[1..4].iter().all(|c| c.parse::<f64>().is_ok()),
            "{row}"
        );
    }
    assert!(text.contains("calibrated, real-like"), "{text}");
    let row = text
        .lines()
        .find(|l| l.starts_with("| nitinol-2mm-630 | c1 |"))
        .expect("a Table I row");
    assert!(
        !row.contains('–'),
        "every cell of ours and the paper's filled: {row}"
    );
    // The page: the same tables, the figures embedded, nothing loaded from the network.
    for part in [
        "<h3>Table I",
        "<h3>Table III",
        "<td>nitinol-2mm-630</td><td>c1</td>",
    ] {
        assert!(html.contains(part), "{part} in report.html");
    }
    assert!(html.contains("src=\"data:image/png;base64,"));
    assert!(!html.contains("src=\"http"));
    let output = ftwire(&["reproduce", "--quick", "--jobs", "0", "--out", "x"]);
    assert_exit(&output, 2, "--jobs 0", "no jobs");
    let out = dir.join("bad-sensor");
    let output = ftwire(&[
        "reproduce",
        "--quick",
        "--sensor",
        "/no/such/sensor.toml",
        "--out",
        out.to_str().expect("UTF-8"),
    ]);
    assert_exit(&output, 2, "sensor.toml", "a missing sensor file");
    assert!(!out.exists(), "nothing written for bad input");
    // A results page the user wrote is refused before anything runs, and left as it was.
    let theirs = dir.join("their-docs");
    fs::create_dir_all(&theirs).expect("creates their docs");
    fs::write(theirs.join("results.md"), "# My results\n").expect("writes their page");
    let out = dir.join("refused");
    let output = ftwire(&[
        "reproduce",
        "--quick",
        "--docs",
        theirs.to_str().expect("UTF-8"),
        "--out",
        out.to_str().expect("UTF-8"),
    ]);
    assert_exit(
        &output,
        2,
        "not written by ftwire reproduce",
        "a user's results.md",
    );
    assert!(!out.exists(), "nothing run for a refused --docs");
    assert_eq!(
        fs::read_to_string(theirs.join("results.md")).expect("their page"),
        "# My results\n"
    );
    let _ = fs::remove_dir_all(&dir);
}
