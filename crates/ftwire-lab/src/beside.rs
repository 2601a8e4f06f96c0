//! The paper's tables beside ours: the Markdown report of a reproduction (`ftwire reproduce`'s
//! `report.md`, and the tables of `docs/results.md`), read from the experiments'
//! `summary.json` files. Every text read from a summary goes in as literal text.

use std::fmt::Write as _;
use std::path::Path;

use ftwire_report::html::{code_span, escape_markdown};
use serde_json::Value;

use crate::paper::{PASSAGE_ATTEMPTS, PASSAGE_SUCCESSES, TABLE_I, TABLE_II, TABLE_III, TABLE_IV};

/// An experiment's `summary` object, if it ran.
fn summary_of(dir: &Path, id: &str) -> Option<Value> {
    let text = std::fs::read_to_string(dir.join(id).join("summary.json")).ok()?;
    let value: Value = serde_json::from_str(&text).ok()?;
    value.get("summary").cloned()
}

fn percent(v: &Value) -> String {
    v.as_f64()
        .map_or_else(|| "–".to_owned(), |x| format!("{:.2}", 100.0 * x))
}

fn number(v: &Value, digits: usize) -> String {
    v.as_f64()
        .map_or_else(|| "–".to_owned(), |x| format!("{x:.digits$}"))
}

/// `report.md` of a reproduction in `dir` (one subfolder per experiment, each with its
/// `summary.json`): the experiments' `(id, status)`, then the paper's tables beside ours. `sensor` is Markdown; every text read from the
/// experiments' summaries and statuses goes in as literal text.
pub fn report(dir: &Path, statuses: &[(&str, &str)], quick: bool, sensor: &str) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# ftwire against Mishani & Sintov (RA-L 2022), §IV\n\nIn the simulator, gravity on, \
         {sensor} through the learnt calibration{}. Each experiment's own folder has its full \
         summary, figures and log.\n\nWhat to expect on a real rig: the columns and rows marked \
         *real-like* repeat an experiment with the `real-like` recording preset (`--sensor \
         real-like --protocol single-readings`: the sensor as a real recording shows it, offsets, \
         a weak torsion channel, one reading's scatter and hysteresis, and its calibration \
         session recorded as single readings on a wire that softens as nitinol does; \
         `docs/real-rig.md`){}.\n",
        if quick {
            "; **quick run** (reduced trial counts)"
        } else {
            ""
        },
        if quick {
            ", in a quick run Table II's only"
        } else {
            ""
        }
    );
    let _ = writeln!(md, "| experiment | status |\n| --- | --- |");
    for (id, status) in statuses {
        let _ = writeln!(md, "| {} | {} |", code_span(id), escape_markdown(status));
    }
    md.push('\n');
    if let Some(s) = summary_of(dir, "identify") {
        identification_table(&mut md, &s);
    }
    if let Some(s) = summary_of(dir, "calibrate") {
        let _ = writeln!(
            md,
            "## §IV-A: the learnt F/T calibration\n\nOn the test split of the known wire \
             ({}): relative error of `ã` against the true wrench, and the shape error of \
             Φ(ã).\n\n| map | torque % | force % | shape mm |\n| --- | --- | --- | --- |",
            escape_markdown(s["wire"]["name"].as_str().unwrap_or("?")),
        );
        let real_like = summary_of(dir, "calibrate_real_like");
        let runs = [("", Some(&s)), (", real-like", real_like.as_ref())];
        for (suffix, run) in runs {
            let Some(run) = run else { continue };
            for (key, label) in [("raw", "raw (mounting only)"), ("calibrated", "calibrated")] {
                let _ = writeln!(
                    md,
                    "| {label}{suffix} | {} | {} | {} |",
                    percent(&run[key]["torque_rel"]),
                    percent(&run[key]["force_rel"]),
                    number(&run[key]["shape_mm"], 2),
                );
            }
        }
        md.push('\n');
    }
    if let Some(s) = summary_of(dir, "shape") {
        let real_like = summary_of(dir, "shape_real_like");
        let _ = writeln!(
            md,
            "## Table II: shape from F/T, mean distance to the true wire [mm]\n\n\
             | wire | ours, loaded model | ours, the paper's model (same ã) | real-like, loaded \
             model | paper |\n| --- | --- | --- | --- | --- |"
        );
        for wire in s["wires"].as_array().into_iter().flatten() {
            let name = wire["name"].as_str().unwrap_or("?");
            let paper = TABLE_II
                .iter()
                .find(|(n, _)| *n == name)
                .map_or_else(|| "–".to_owned(), |(_, mm)| format!("{mm:.2}"));
            let realistic = real_like
                .as_ref()
                .and_then(|r| {
                    r["wires"]
                        .as_array()
                        .and_then(|ws| ws.iter().find(|w| w["name"] == name))
                        .map(|w| number(&w["loaded_mean_mm"], 2))
                })
                .unwrap_or_else(|| "–".to_owned());
            let _ = writeln!(
                md,
                "| {} | {} | {} | {realistic} | {paper} |",
                escape_markdown(name),
                number(&wire["loaded_mean_mm"], 2),
                number(&wire["kirchhoff_mean_mm"], 2),
            );
        }
        md.push('\n');
    }
    if let Some(s) = summary_of(dir, "goal") {
        goal_table(&mut md, &s, summary_of(dir, "goal_real_like").as_ref());
    }
    if let Some(s) = summary_of(dir, "track") {
        track_table(&mut md, &s, summary_of(dir, "track_real_like").as_ref());
    }
    let passages: Vec<(Value, &str)> = [
        ("passage", ""),
        ("passage_offset", ""),
        ("passage_real_like", " (real-like)"),
    ]
    .iter()
    .filter_map(|(id, label)| summary_of(dir, id).map(|s| (s, *label)))
    .collect();
    if !passages.is_empty() {
        passage_table(&mut md, &passages);
    }
    md
}

/// Table IV: tracking planned paths, ours (and the real-like run's, if there is one) beside
/// the paper's.
fn track_table(md: &mut String, s: &Value, real_like: Option<&Value>) {
    let _ = writeln!(
        md,
        "## Table IV: tracking a path planned with RRT* ({} pairs, noise model {}, gain {})\n\n\
         Distance [mm] between the true wire and Φ(γ_A) at each waypoint reached, over every \
         waypoint of every pair (the planning times are in the experiment's `timings.json`).\n\n\
         | | mean ± std | max | waypoints | paper, mean ± std |\n| --- | --- | --- | --- | --- |",
        number(&s["pairs"], 0),
        code_span(s["noise_model"].as_str().unwrap_or("?")),
        number(&s["gain"], 2),
    );
    let (open, closed, closed_std) = TABLE_IV;
    let rows = [
        ("open_loop", "open loop", format!("{open:.2}")),
        (
            "closed_loop",
            "closed loop",
            format!("{closed:.2} ± {closed_std:.2}"),
        ),
    ];
    let runs = [(s, ""), (real_like.unwrap_or(&Value::Null), ", real-like")];
    for ((run, suffix), (key, label, paper)) in runs
        .iter()
        .filter(|(run, _)| !run.is_null())
        .flat_map(|run| rows.iter().map(move |row| (run, row)))
    {
        let r = &run["results"][key];
        let _ = writeln!(
            md,
            "| {label}{suffix} | {} ± {} | {} | {} | {paper} |",
            number(&r["mean_mm"], 2),
            number(&r["std_mm"], 2),
            number(&r["max_mm"], 2),
            number(&r["waypoints"], 0),
        );
    }
    md.push('\n');
}

/// §IV-E: the passage success rates, ours beside the paper's ([`PASSAGE_SUCCESSES`] of
/// [`PASSAGE_ATTEMPTS`], with the paper's noise).
fn passage_table(md: &mut String, runs: &[(Value, &str)]) {
    let _ = writeln!(
        md,
        "## §IV-E: through the 50 mm passage\n\nSuccess: the whole path executed and the true \
         wire never touched a box; under `offset` it must also end within the success tolerance \
         of the goal, under `increment` (whose every move lands the wire the full noise away) \
         the paper's rule, no collision, decides. At goal: completed within the tolerance, under \
         every noise model. Collisions: the true wire touched a box; detected: of those, stopped \
         by the collision detector.\n\n\
         | noise model | mode | successes | at goal | collisions | detected | false alarms | paper |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- |"
    );
    let rate = |successes: usize| format!("{successes}/{PASSAGE_ATTEMPTS} (increment)");
    let (open, closed) = (rate(PASSAGE_SUCCESSES.0), rate(PASSAGE_SUCCESSES.1));
    for (s, suffix) in runs {
        let noise = s["noise_model"].as_str().unwrap_or("?");
        for (key, label, paper) in [
            ("open_loop", "open loop", open.as_str()),
            ("closed_loop", "closed loop", closed.as_str()),
        ] {
            let r = &s["results"][key];
            let _ = writeln!(
                md,
                "| {} | {label}{suffix} | {}/{} | {} | {} | {} | {} | {} |",
                code_span(noise),
                number(&r["successes"], 0),
                number(&r["attempts"], 0),
                number(&r["at_goal"], 0),
                number(&r["collisions"], 0),
                number(&r["detected"], 0),
                number(&r["false_alarms"], 0),
                if noise == "increment" { paper } else { "–" },
            );
        }
    }
    md.push('\n');
}

/// Table I: identification from 3 samples, ours (both models) beside the paper's.
fn identification_table(md: &mut String, s: &Value) {
    let _ = writeln!(
        md,
        "## Table I: identification from 3 samples\n\nOurs: mean ± std over the trials and the \
         error of the mean (as the paper's), then the mean of each trial's absolute error; the \
         loaded model (which also identifies the weight), and the paper's weightless model on \
         the same data.\n\n| wire | parameter | true | ours, loaded | error of mean % | mean \
         abs. error % | paper's model: mean abs. error % | paper | paper error % |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    );
    let models = s["by_model"].as_array().cloned().unwrap_or_default();
    let model = |name: &str| {
        models
            .iter()
            .find(|m| m["model"] == name)
            .map(|m| m["wires"].clone())
    };
    let (Some(loaded), other) = (model("loaded"), model("kirchhoff")) else {
        return;
    };
    let names = ["c1", "c2", "c3", "L"];
    for (w, wire) in loaded.as_array().into_iter().flatten().enumerate() {
        let name = wire["wire"]["name"].as_str().unwrap_or("?");
        let row = &wire["by_samples"][0];
        let other_row = other.as_ref().map(|o| o[w]["by_samples"][0].clone());
        let paper = TABLE_I
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, rows)| rows);
        for (j, parameter) in names.iter().enumerate() {
            let truth = if j < 3 {
                &wire["wire"]["c"][j]
            } else {
                &wire["wire"]["length"]
            };
            let (paper_value, paper_error) = paper.map_or_else(
                || ("–".to_owned(), "–".to_owned()),
                |rows| {
                    let (_, mean, std, error) = rows[j];
                    (format!("{mean:.3} ± {std:.3}"), format!("{error:.1}"))
                },
            );
            let _ = writeln!(
                md,
                "| {} | {parameter} | {} | {} ± {} | {} | {} | {} | {paper_value} | \
                 {paper_error} |",
                escape_markdown(name),
                number(truth, 3),
                number(&row["mean"][j], 4),
                number(&row["std"][j], 4),
                percent(&row["relative_error"][j].as_f64().map(f64::abs).into()),
                percent(&row["mean_abs_relative_error"][j]),
                other_row.as_ref().map_or_else(
                    || "–".to_owned(),
                    |r| percent(&r["mean_abs_relative_error"][j])
                ),
            );
        }
    }
    md.push('\n');
}

/// Table III: goal reaching, ours (and the real-like run's, if there is one) beside the
/// paper's.
fn goal_table(md: &mut String, s: &Value, real_like: Option<&Value>) {
    let _ = writeln!(
        md,
        "## Table III: reaching a goal in A ({} pairs, noise model {})\n\nMean distance \
         [mm] between the true final shape and Φ(a_g) (± std), the trials counted (failed runs \
         and simulator failures are left out and listed in the experiment's summary), and the \
         mean over the trials in which the simulated wire did not snap to another shape.\n\n\
         | | ours, open loop | ours, closed loop | real-like, open loop | real-like, closed \
         loop | paper, open loop | paper, closed loop |\n\
         | --- | --- | --- | --- | --- | --- | --- |",
        number(&s["pairs"], 0),
        code_span(s["noise_model"].as_str().unwrap_or("?")),
    );
    let cell = |v: &Value| {
        format!(
            "{} ± {} ({} trials; {} without snaps)",
            number(&v["mean_mm"], 2),
            number(&v["std_mm"], 2),
            number(&v["trials"], 0),
            number(&v["mean_mm_without_snaps"], 2),
        )
    };
    for (key, open, closed) in TABLE_III {
        let realistic = |mode: &str| {
            real_like.map_or_else(|| "–".to_owned(), |r| cell(&r["results"][mode][key]))
        };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {open:.2} | {closed:.2} |",
            key.replace('_', " "),
            cell(&s["results"]["open_loop"][key]),
            cell(&s["results"]["closed_loop"][key]),
            realistic("open_loop"),
            realistic("closed_loop"),
        );
    }
    let c = &s["collision"];
    let _ = writeln!(
        md,
        "\nSteps (median, with noise): {}. Collision detection: {} false alarms in {} free \
         motions; {} of {} contacts detected, median delay {} steps.\n",
        number(&s["steps_median"], 1),
        number(&c["false_alarms"], 0),
        number(&c["free_motions"], 0),
        number(&c["detected"], 0),
        number(&c["trials"], 0),
        number(&c["detection_delay_steps_median"], 1),
    );
}
