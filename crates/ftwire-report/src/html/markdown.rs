//! The small subset of Markdown that ftwire's reports are written in, as HTML: `#` headings,
//! paragraphs, pipe tables (a header row, a `---` row, body rows), inline `` `code` `` and
//! `**bold**`, and CommonMark's backslash escapes (`\*` is a literal `*`; `\|` a literal `|`
//! in a table cell, code included). Everything else is text, escaped.
//!
//! [`escape_markdown`] and [`code_span`] put text that came from a user (a wire's name, a file's
//! path) into that Markdown as literal text: no row break, heading, link, emphasis or raw HTML.

use std::fmt::Write as _;

use super::text::escape;

/// The characters [`escape_markdown`] puts a backslash before: those that open markup inline in
/// CommonMark and GitHub Markdown (escapes, code, emphasis, strikethrough, links and images,
/// raw HTML and autolinks, character references), a heading's `#`, and a table's `|`.
const SPECIAL: &[char] = &['\\', '`', '*', '_', '~', '[', ']', '<', '>', '&', '#', '|'];

/// `text` as literal Markdown text: `` \ ` * _ ~ [ ] < > & # | `` backslash-escaped (what can
/// open inline markup, a heading or a table cell) and line breaks (`\n`, `\r`) turned into spaces, so that it stays inside its line, paragraph or table cell
/// and renders as itself (here and in CommonMark and GitHub Markdown).
///
/// # Example
/// ```
/// use ftwire_report::html::escape_markdown;
/// assert_eq!(escape_markdown("a|b\n<i>"), "a\\|b \\<i\\>");
/// assert_eq!(escape_markdown("nitinol-2mm-630"), "nitinol-2mm-630");
/// ```
pub fn escape_markdown(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '\n' | '\r' => out.push(' '),
            c if SPECIAL.contains(&c) => {
                out.push('\\');
                out.push(c);
            }
            c => out.push(c),
        }
    }
    out
}

/// `text` as an inline code span: `` `text` `` with `|` escaped (GitHub tables split on it
/// even inside code) and line breaks as spaces; text with a backtick, which no single-backtick
/// span can hold, is [`escape_markdown`]d instead.
///
/// # Example
/// ```
/// use ftwire_report::html::code_span;
/// assert_eq!(code_span("plan.choice"), "`plan.choice`");
/// assert_eq!(code_span("a|b"), "`a\\|b`");
/// assert_eq!(code_span("a`b"), "a\\`b");
/// ```
pub fn code_span(text: &str) -> String {
    if text.contains('`') {
        return escape_markdown(text);
    }
    let inner: String = text
        .chars()
        .map(|c| if matches!(c, '\n' | '\r') { ' ' } else { c })
        .collect();
    format!("`{}`", inner.replace('|', "\\|"))
}

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

/// The cells of a table row `| a | b |`, split at the pipes not escaped as `\|`; an escaped
/// pipe is a literal `|` in its cell (as in GitHub's tables, code spans included).
fn cells(row: &str) -> Vec<String> {
    let row = row.trim();
    let row = row.strip_prefix('|').unwrap_or(row);
    let row = match row.strip_suffix('|') {
        Some(rest) if !ends_escaped(rest) => rest,
        _ => row,
    };
    let mut cells = Vec::new();
    let mut cell = String::new();
    let mut chars = row.chars();
    while let Some(c) = chars.next() {
        match c {
            '\\' => match chars.next() {
                Some('|') => cell.push('|'),
                Some(next) => {
                    cell.push('\\');
                    cell.push(next);
                }
                None => cell.push('\\'),
            },
            '|' => cells.push(std::mem::take(&mut cell).trim().to_owned()),
            c => cell.push(c),
        }
    }
    cells.push(cell.trim().to_owned());
    cells
}

/// Whether `text` ends in an odd run of backslashes (its next character is escaped).
fn ends_escaped(text: &str) -> bool {
    text.chars().rev().take_while(|&c| c == '\\').count() % 2 == 1
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
            let _ = write!(html, "<{tag}>{}</{tag}>", inline(&cell));
        }
        html.push_str("</tr>\n");
    }
    html.push_str("</table>\n");
    rows.clear();
}

/// Inline markup: `` `code` `` (verbatim inside; a backtick without its closing one is text),
/// `**bold**`, and `\` before ASCII punctuation for the character itself; the rest escaped.
fn inline(text: &str) -> String {
    let mut out = String::new();
    let mut bold = false;
    let mut rest = text;
    while let Some(c) = rest.chars().next() {
        let after = &rest[c.len_utf8()..];
        if c == '\\' {
            if let Some(next) = after.chars().next().filter(char::is_ascii_punctuation) {
                out.push_str(&escape(&next.to_string()));
                rest = &after[next.len_utf8()..];
                continue;
            }
        } else if c == '`' {
            if let Some(end) = after.find('`') {
                let _ = write!(out, "<code>{}</code>", escape(&after[..end]));
                rest = &after[end + 1..];
                continue;
            }
        } else if let Some(tail) = rest.strip_prefix("**") {
            out.push_str(if bold { "</strong>" } else { "<strong>" });
            bold = !bold;
            rest = tail;
            continue;
        }
        out.push_str(&escape(&c.to_string()));
        rest = after;
    }
    if bold {
        out.push_str("</strong>");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{code_span, escape_markdown, to_html};

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

    #[test]
    fn escaped_text_renders_as_itself_in_a_paragraph_and_a_cell() {
        let name = "=1+2,\"evil\" | **x** _y_ [l](u) `c` \\ # <script>x</script>\nnext";
        let shown = "=1+2,&quot;evil&quot; | **x** _y_ [l](u) `c` \\ # \
                     &lt;script&gt;x&lt;/script&gt; next";
        assert_eq!(
            to_html(&format!("Wire {}.", escape_markdown(name))),
            format!("<p>Wire {shown}.</p>\n")
        );
        let html = to_html(&format!(
            "| key | value |\n| --- | --- |\n| {} | {} |\n",
            code_span("a|b"),
            escape_markdown(name)
        ));
        assert_eq!(
            html,
            format!(
                "<table>\n<tr><th>key</th><th>value</th></tr>\n\
                 <tr><td><code>a|b</code></td><td>{shown}</td></tr>\n</table>\n"
            )
        );
        let escaped = escape_markdown(name);
        assert!(
            !escaped.contains('\n') && !escaped.contains("<script>"),
            "{escaped}"
        );
    }

    #[test]
    fn a_lone_backtick_and_a_trailing_escaped_pipe_are_text() {
        assert_eq!(to_html("a ` b"), "<p>a ` b</p>\n");
        assert_eq!(
            to_html("| a | b\\|\n"),
            "<table>\n<tr><td>a</td><td>b|</td></tr>\n</table>\n"
        );
    }
}
