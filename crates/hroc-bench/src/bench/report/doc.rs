//! The report as a list of blocks, written once and rendered twice: as
//! Markdown (report.md) and as a self-contained HTML page (index.html).

use std::fmt::Write;

pub struct Table {
    pub head: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl Table {
    pub fn new(head: &[&str]) -> Self {
        Table { head: head.iter().map(|s| s.to_string()).collect(), rows: Vec::new() }
    }
    pub fn row(&mut self, cells: Vec<String>) {
        self.rows.push(cells);
    }
}

pub enum Block {
    Heading(String),
    Para(String),
    Table(Table),
    /// Images side by side: (path relative to the report folder, caption).
    Images(Vec<(String, String)>),
    /// Preformatted text (commands).
    Code(String),
}

#[derive(Default)]
pub struct Doc {
    pub title: String,
    pub blocks: Vec<Block>,
}

impl Doc {
    pub fn heading(&mut self, s: impl Into<String>) {
        self.blocks.push(Block::Heading(s.into()));
    }
    pub fn para(&mut self, s: impl Into<String>) {
        self.blocks.push(Block::Para(s.into()));
    }
    pub fn table(&mut self, t: Table) {
        self.blocks.push(Block::Table(t));
    }
    pub fn images(&mut self, imgs: Vec<(String, String)>) {
        self.blocks.push(Block::Images(imgs));
    }
    pub fn code(&mut self, s: impl Into<String>) {
        self.blocks.push(Block::Code(s.into()));
    }

    pub fn markdown(&self) -> String {
        let mut out = format!("# {}\n", self.title);
        for b in &self.blocks {
            out.push('\n');
            match b {
                Block::Heading(s) => {
                    let _ = writeln!(out, "## {s}");
                }
                Block::Para(s) => {
                    let _ = writeln!(out, "{s}");
                }
                Block::Code(s) => {
                    let _ = writeln!(out, "```\n{s}\n```");
                }
                Block::Table(t) => {
                    let cell = |s: &String| s.replace('|', "\\|");
                    let _ = writeln!(out, "| {} |", t.head.iter().map(cell).collect::<Vec<_>>().join(" | "));
                    let _ = writeln!(out, "|{}|", t.head.iter().enumerate().map(|(i, _)| if i == 0 { ":--" } else { "--:" }).collect::<Vec<_>>().join("|"));
                    for r in &t.rows {
                        let _ = writeln!(out, "| {} |", r.iter().map(cell).collect::<Vec<_>>().join(" | "));
                    }
                }
                Block::Images(imgs) => {
                    // Markdown viewers show PNG everywhere; SVG sits beside it.
                    for (path, caption) in imgs {
                        let png = path.strip_suffix(".svg").map_or(path.clone(), |s| format!("{s}.png"));
                        let _ = writeln!(out, "![{caption}]({png})");
                    }
                    let _ = writeln!(out, "\n{}", imgs.iter().map(|(_, c)| format!("*{c}*")).collect::<Vec<_>>().join(" · "));
                }
            }
        }
        out
    }

    /// One page, no external resources but the images it shows; a script
    /// counts the images that loaded and failed into `<body data-…>` so a
    /// headless browser can tell a complete page from a broken one.
    pub fn html(&self) -> String {
        let mut out = String::new();
        let _ = write!(
            out,
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n<style>{CSS}</style>\n</head>\n<body>\n<h1>{}</h1>\n",
            esc(&self.title),
            esc(&self.title)
        );
        for b in &self.blocks {
            match b {
                Block::Heading(s) => {
                    let _ = writeln!(out, "<h2>{}</h2>", esc(s));
                }
                Block::Para(s) => {
                    let _ = writeln!(out, "<p>{}</p>", inline(s));
                }
                Block::Code(s) => {
                    let _ = writeln!(out, "<pre>{}</pre>", esc(s));
                }
                Block::Table(t) => {
                    out.push_str("<table>\n<thead><tr>");
                    for h in &t.head {
                        let _ = write!(out, "<th>{}</th>", esc(h));
                    }
                    out.push_str("</tr></thead>\n<tbody>\n");
                    for r in &t.rows {
                        out.push_str("<tr>");
                        for c in r {
                            let _ = write!(out, "<td>{}</td>", inline(c));
                        }
                        out.push_str("</tr>\n");
                    }
                    out.push_str("</tbody>\n</table>\n");
                }
                Block::Images(imgs) => {
                    out.push_str("<div class=\"figs\">\n");
                    for (path, caption) in imgs {
                        let _ = writeln!(out, "<figure><img src=\"{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>", esc(path), esc(caption), esc(caption));
                    }
                    out.push_str("</div>\n");
                }
            }
        }
        out.push_str(SCRIPT);
        out.push_str("</body>\n</html>\n");
        out
    }
}

const CSS: &str = "body{font-family:system-ui,sans-serif;max-width:1200px;margin:2em auto;padding:0 1em;color:#222}\
table{border-collapse:collapse;margin:1em 0;font-size:14px}th,td{border:1px solid #ccc;padding:3px 8px;text-align:right}\
th:first-child,td:first-child{text-align:left}th{background:#f0f0f0}pre{background:#f6f6f6;padding:8px;overflow-x:auto}\
.figs{display:flex;flex-wrap:wrap;gap:12px}figure{margin:0}figure img{max-width:100%;border:1px solid #ddd}\
figcaption{font-size:13px;color:#555;text-align:center}";

const SCRIPT: &str = "<script>\nwindow.addEventListener('load', () => {\n  const imgs = [...document.images];\n  document.body.dataset.imagesLoaded = imgs.filter(i => i.complete && i.naturalWidth > 0).length;\n  document.body.dataset.imagesFailed = imgs.filter(i => !(i.complete && i.naturalWidth > 0)).length;\n});\n</script>\n";

pub fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// Escapes, then turns Markdown's `code` and **bold** into HTML.
fn inline(s: &str) -> String {
    let mut out = String::new();
    for (i, part) in esc(s).split('`').enumerate() {
        if i % 2 == 1 {
            let _ = write!(out, "<code>{part}</code>");
        } else {
            for (j, p) in part.split("**").enumerate() {
                if j % 2 == 1 {
                    let _ = write!(out, "<b>{p}</b>");
                } else {
                    out.push_str(p);
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doc() -> Doc {
        let mut d = Doc { title: "T <1>".into(), ..Default::default() };
        d.heading("H");
        d.para("a `b<c>` **d**");
        let mut t = Table::new(&["m", "ms"]);
        t.row(vec!["x|y".into(), "1.0".into()]);
        d.table(t);
        d.images(vec![("plots/a.svg".into(), "cap".into())]);
        d
    }

    #[test]
    fn markdown_escapes_pipes_and_links_png() {
        let md = doc().markdown();
        assert!(md.starts_with("# T <1>\n"));
        assert!(md.contains("| x\\|y | 1.0 |"), "{md}");
        assert!(md.contains("![cap](plots/a.png)"), "{md}");
    }

    #[test]
    fn html_escapes_and_counts_images() {
        let h = doc().html();
        assert!(h.contains("<title>T &lt;1&gt;</title>"));
        assert!(h.contains("a <code>b&lt;c&gt;</code> <b>d</b>"), "{h}");
        assert!(h.contains("<img src=\"plots/a.svg\""));
        assert!(h.contains("imagesLoaded"));
        assert_eq!(h.matches("<table>").count(), h.matches("</table>").count());
    }
}
