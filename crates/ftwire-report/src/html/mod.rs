//! `report.html`: one self-contained page per results folder, readable offline.
//!
//! An [`HtmlReport`] is built from Markdown (the subset ftwire's `report.md` uses: headings,
//! paragraphs, pipe tables, `` `code` ``, `**bold**`), paragraphs, PNG figures (embedded as
//! base64 `data:` URLs) and interactive 3-D views ([`Scene3d`]: obstacles, and a slider over
//! the steps of a motion with named centrelines and the grippers). The views are drawn by
//! three.js, vendored in `vendor/three/` (version, license and how to update it in its
//! README) and embedded in the page as a `data:` module, so the page loads nothing from the
//! network. A page without views carries no JavaScript library at all.
//!
//! The page records its own errors and whether each view drew anything on its `<html>`
//! element (`data-errors`, `data-canvas`, `data-views`), which the browser test
//! `.ci/browser-test` reads from headless Chromium. The same inputs give the same bytes (no
//! timestamps).
//!
//! ```
//! use ftwire_report::{HtmlReport, Scene3d, Step3, IDENTITY};
//! let view = Scene3d::new("the wire")
//!     .with_box("box", [0.3, 0.0, 0.1], [0.05, 0.05, 0.1], IDENTITY)
//!     .with_step(Step3::new("rest 1").with_polyline("truth", vec![[0.0; 3], [0.2, 0.0, 0.1]]));
//! let html = HtmlReport::new("demo")
//!     .with_markdown("## Results\n\n| a | b |\n| --- | --- |\n| 1 | 2 |")
//!     .with_scene(view)
//!     .to_html();
//! assert!(html.starts_with("<!DOCTYPE html>"));
//! assert!(html.contains("<th>a</th>"));
//! assert!(!html.contains("src=\"http"));
//! ```

mod base64;
mod markdown;
mod scene;
mod text;

use std::fmt::Write as _;
use std::path::Path;

pub use markdown::{code_span, escape_markdown};
pub use scene::{Box3, Gripper3, IDENTITY, Polyline3, RESOLUTION, Rotation, Scene3d, Step3};
use text::escape;

use crate::ReportError;

/// three.js's single-file ES module build (`vendor/three/README.md`).
const THREE: &str = include_str!("../../vendor/three/three.module.min.js");
/// The hand-written viewer of the 3-D views.
const VIEWER: &str = include_str!("viewer.js");
/// The first script of the page: records errors on `<html data-errors>`.
const GUARD: &str = include_str!("guard.js");
/// The page's style.
const STYLE: &str = include_str!("report.css");

/// A self-contained HTML report, built in reading order.
#[derive(Debug, Clone, Default)]
#[must_use]
pub struct HtmlReport {
    title: String,
    /// The body's HTML so far (views as placeholders `data-view="k"`).
    body: String,
    scenes: Vec<Scene3d>,
}

/// JSON made safe inside a `<script>` element: `<`, `>` and `&` as `\u` escapes (still the same
/// JSON), so no `</script>` or `<!--` can appear.
fn script_json(json: &str) -> String {
    json.replace('<', "\\u003c")
        .replace('>', "\\u003e")
        .replace('&', "\\u0026")
}

impl HtmlReport {
    /// An empty report titled `title` (the page's `<title>` and `<h1>`).
    pub fn new(title: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            ..Self::default()
        }
    }

    /// Appends `markdown` (headings, paragraphs, pipe tables, `` `code` ``, `**bold**`; `#` is
    /// a section, one level below the title).
    pub fn with_markdown(mut self, markdown: &str) -> Self {
        self.body.push_str(&markdown::to_html(markdown));
        self
    }

    /// Appends a paragraph of plain text.
    pub fn with_paragraph(mut self, text: &str) -> Self {
        let _ = writeln!(self.body, "<p>{}</p>", escape(text));
        self
    }

    /// Appends a PNG figure from its bytes, with a caption.
    pub fn with_png(mut self, caption: &str, png: &[u8]) -> Self {
        let _ = writeln!(
            self.body,
            "<figure><img alt=\"{0}\" src=\"data:image/png;base64,{1}\">\
             <figcaption>{0}</figcaption></figure>",
            escape(caption),
            base64::encode(png)
        );
        self
    }

    /// Appends the PNG file `path` as a figure, with a caption.
    ///
    /// # Errors
    /// [`ReportError::Io`] when the file cannot be read.
    pub fn with_png_file(self, caption: &str, path: &Path) -> Result<Self, ReportError> {
        let png = std::fs::read(path).map_err(|source| ReportError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Ok(self.with_png(caption, &png))
    }

    /// Appends an interactive 3-D view.
    pub fn with_scene(mut self, scene: Scene3d) -> Self {
        let _ = writeln!(
            self.body,
            "<h2>{}</h2>\n<p class=\"hint\">Drag to turn, wheel to zoom, double-click to reset; \
             the slider walks through the steps.</p>\n<div class=\"view\" data-view=\"{}\"></div>",
            escape(&scene.title),
            self.scenes.len()
        );
        self.scenes.push(scene);
        self
    }

    /// The page.
    #[must_use]
    pub fn to_html(&self) -> String {
        let mut page = String::new();
        let _ = write!(
            page,
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
             <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
             <title>{title}</title>\n<style>\n{STYLE}</style>\n<script>\n{GUARD}</script>\n\
             </head>\n<body>\n<h1>{title}</h1>\n{body}",
            title = escape(&self.title),
            body = self.body,
        );
        if !self.scenes.is_empty() {
            // Non-finite numbers become `null`, which the viewer skips; serialising plain
            // data to a string cannot fail otherwise.
            let json = serde_json::to_string(&self.scenes).unwrap_or_else(|_| "[]".to_owned());
            let _ = write!(
                page,
                "<script type=\"application/json\" id=\"ftwire-scenes\">{}</script>\n\
                 <script type=\"module\">\nimport * as THREE from \
                 \"data:text/javascript;base64,{}\";\n{VIEWER}</script>\n",
                script_json(&json),
                base64::encode(THREE.as_bytes()),
            );
        }
        page.push_str("</body>\n</html>\n");
        page
    }

    /// Writes the page to `path`.
    ///
    /// # Errors
    /// [`ReportError::Io`] when the file cannot be written.
    pub fn write(&self, path: &Path) -> Result<(), ReportError> {
        std::fs::write(path, self.to_html()).map_err(|source| ReportError::Io {
            path: path.to_path_buf(),
            source,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::{HtmlReport, IDENTITY, Scene3d, Step3, escape, script_json};

    #[test]
    fn text_is_escaped() {
        assert_eq!(escape("a<b & \"c\"'"), "a&lt;b &amp; &quot;c&quot;&#39;");
        let html = HtmlReport::new("<x>").with_paragraph("</p>").to_html();
        assert!(html.contains("<h1>&lt;x&gt;</h1>"));
        assert!(html.contains("<p>&lt;/p&gt;</p>"));
    }

    #[test]
    fn json_in_a_script_cannot_close_it() {
        let view = Scene3d::new("t").with_step(
            Step3::new("</script><!--").with_polyline("a&b", vec![[0.0, 1.0, f64::NAN]]),
        );
        let html = HtmlReport::new("t").with_scene(view).to_html();
        let start = html.find("id=\"ftwire-scenes\">").expect("the data") + 19;
        let end = start + html[start..].find("</script>").expect("its end");
        let data = &html[start..end];
        assert!(!data.contains('<') && !data.contains('>') && !data.contains('&'));
        let back: serde_json::Value = serde_json::from_str(data).expect("still JSON");
        assert_eq!(back[0]["steps"][0]["label"], "</script><!--");
        assert_eq!(back[0]["steps"][0]["polylines"][0]["name"], "a&b");
        assert!(back[0]["steps"][0]["polylines"][0]["points"][0][2].is_null());
        assert_eq!(script_json("\"</\""), "\"\\u003c/\"");
    }

    #[test]
    fn the_page_loads_nothing_from_the_network() {
        let view = Scene3d::new("v")
            .with_box("b", [0.0; 3], [0.1; 3], IDENTITY)
            .with_step(Step3::new("s").with_gripper("base", [0.0; 3], Some(IDENTITY)));
        let html = HtmlReport::new("t")
            .with_png("fig", &[0x89, b'P', b'N', b'G'])
            .with_scene(view)
            .to_html();
        for pattern in [
            "src=\"http",
            "href=\"http",
            "from \"http",
            "import(\"http",
            "url(http",
        ] {
            assert!(!html.contains(pattern), "{pattern}");
        }
        assert!(html.contains("src=\"data:image/png;base64,iVBORw==\""));
        assert!(html.contains("import * as THREE from \"data:text/javascript;base64,"));
        assert_eq!(html.matches("<script").count(), 3);
        assert_eq!(html.matches("</script>").count(), 3);
        assert!(html.ends_with("</body>\n</html>\n"));
    }

    #[test]
    fn points_are_kept_to_ten_micrometres() {
        let view = Scene3d::new("v").with_polyline("p", vec![[0.123_456_78, -1e-7, f64::NAN]]);
        let p = view.polylines[0].points[0];
        approx::assert_abs_diff_eq!(p[0], 0.123_46, epsilon = 1e-12);
        approx::assert_abs_diff_eq!(p[1], 0.0, epsilon = 1e-12);
        assert!(p[2].is_nan());
        let html = HtmlReport::new("t").with_scene(view).to_html();
        assert!(html.contains("\"points\":[[0.12346,0.0,null]]"));
    }

    #[test]
    fn a_page_without_views_has_no_library() {
        let html = HtmlReport::new("t").with_markdown("# a\n\ntext").to_html();
        assert!(!html.contains("type=\"module\""));
        assert!(html.contains("<h2>a</h2>\n<p>text</p>"));
    }

    #[test]
    fn the_same_report_gives_the_same_bytes() {
        let build = || {
            HtmlReport::new("t")
                .with_scene(Scene3d::new("v").with_step(Step3::new("s")))
                .to_html()
        };
        assert_eq!(build(), build());
    }
}
