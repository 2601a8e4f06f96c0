//! The small subset of Markdown that ftwire's reports are written in, as HTML: `#` headings,
//! paragraphs, pipe tables (a header row, a `---` row, body rows), and inline `` `code` `` and
//! `**bold**`. Everything else is text, escaped.

use std::fmt::Write as _;

use super::escape;

/// `markdown` (the subset above) as HTML.
pub(crate) fn to_html(markdown: &str) -> String {
    let mut html = String::new();
    let mut paragraph: Vec<&str> = Vec::new();
    let mut table: Vec<&str> = Vec::new();
    for line in markdown.lines() {
        let line = line.trim_end();
        if !line.starts_with('|') {
            flush_table(&mut html, &mut table);
        }
        if let Some((level, text)) = heading(line) {
            flush_paragraph(&mut html, &mut paragraph);
            let _ = writeln!(html, "<h{level}>{}</h{level}>", inline(text));
        } else if line.starts_with('|') {
            flush_paragraph(&mut html, &mut paragraph);
            table.push(line);
        } else if line.trim().is_empty() {
            flush_paragraph(&mut html, &mut paragraph);
        } else {
            paragraph.push(line.trim());
        }
    }
    flush_table(&mut html, &mut table);
    flush_paragraph(&mut html, &mut paragraph);
    html
}

/// `# text` to `### text`: the level and the text. A section heading of the report is one
/// level below the page's title, so `#` becomes `<h2>`.
fn heading(line: &str) -> Option<(usize, &str)> {
    let hashes = line.bytes().take_while(|&b| b == b'#').count();
    let text = line.get(hashes..)?.strip_prefix(' ')?;
    (1..=4)
        .contains(&hashes)
        .then_some((hashes + 1, text.trim()))
}

fn flush_paragraph(html: &mut String, lines: &mut Vec<&str>) {
    if !lines.is_empty() {
        let _ = writeln!(html, "<p>{}</p>", inline(&lines.join(" ")));
        lines.clear();
    }
}

/// The cells of a table row `| a | b |`.
fn cells(row: &str) -> Vec<&str> {
    let row = row.trim();
    let row = row.strip_prefix('|').unwrap_or(row);
    let row = row.strip_suffix('|').unwrap_or(row);
    row.split('|').map(str::trim).collect()
}

/// A row of dashes (and alignment colons) between the header and the body.
fn is_rule(row: &str) -> bool {
    cells(row)
        .iter()
        .all(|c| !c.is_empty() && c.chars().all(|ch| matches!(ch, '-' | ':')))
}

fn flush_table(html: &mut String, rows: &mut Vec<&str>) {
    if rows.is_empty() {
        return;
    }
    html.push_str("<table>\n");
    let has_header = rows.get(1).is_some_and(|r| is_rule(r));
    for (i, row) in rows.iter().enumerate() {
        if has_header && i == 1 {
            continue;
        }
        let tag = if has_header && i == 0 { "th" } else { "td" };
        html.push_str("<tr>");
        for cell in cells(row) {
            let _ = write!(html, "<{tag}>{}</{tag}>", inline(cell));
        }
        html.push_str("</tr>\n");
    }
    html.push_str("</table>\n");
    rows.clear();
}

/// Inline markup: `` `code` `` (verbatim inside), `**bold**`; the rest escaped.
fn inline(text: &str) -> String {
    let mut out = String::new();
    for (k, part) in text.split('`').enumerate() {
        if k % 2 == 1 {
            let _ = write!(out, "<code>{}</code>", escape(part));
        } else {
            for (j, piece) in escape(part).split("**").enumerate() {
                if j > 0 {
                    out.push_str(if j % 2 == 1 { "<strong>" } else { "</strong>" });
                }
                out.push_str(piece);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::to_html;

    #[test]
    fn headings_paragraphs_and_inline_markup() {
        let html = to_html("# Title\n\nSome `a<b` and **bold**\ntext.\n\n## Next\n");
        assert_eq!(
            html,
            "<h2>Title</h2>\n<p>Some <code>a&lt;b</code> and <strong>bold</strong> text.</p>\n\
             <h3>Next</h3>\n"
        );
    }

    #[test]
    fn a_pipe_table_has_a_header_and_a_body() {
        let html = to_html("| a | b |\n| --- | ---: |\n| 1 | <2> |\n\nafter");
        assert_eq!(
            html,
            "<table>\n<tr><th>a</th><th>b</th></tr>\n<tr><td>1</td><td>&lt;2&gt;</td></tr>\n\
             </table>\n<p>after</p>\n"
        );
    }
}
