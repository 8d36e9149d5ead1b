//! Screenshots: a drawn screen (ratatui's buffer) as SVG text.

use ratatui::buffer::Buffer;
use ratatui::style::{Color, Modifier};
use std::fmt::Write;

const CW: f32 = 8.4;
const CH: f32 = 17.0;

fn hex(c: Color, default: &str) -> String {
    match c {
        Color::Reset => default.to_string(),
        Color::Black => "#000000".into(),
        Color::Red => "#e06c75".into(),
        Color::Green => "#98c379".into(),
        Color::Yellow => "#e5c07b".into(),
        Color::Blue => "#61afef".into(),
        Color::Magenta => "#c678dd".into(),
        Color::Cyan => "#56b6c2".into(),
        Color::Gray => "#abb2bf".into(),
        Color::DarkGray => "#5c6370".into(),
        Color::LightRed => "#f08080".into(),
        Color::LightGreen => "#b5e890".into(),
        Color::LightYellow => "#f0e0a0".into(),
        Color::LightBlue => "#8cc8ff".into(),
        Color::LightMagenta => "#e0a0f0".into(),
        Color::LightCyan => "#90e0e8".into(),
        Color::White => "#ffffff".into(),
        Color::Rgb(r, g, b) => format!("#{r:02x}{g:02x}{b:02x}"),
        Color::Indexed(i) => format!("#{0:02x}{0:02x}{0:02x}", i),
    }
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The buffer as an SVG image, one monospace cell per character.
pub fn buffer_to_svg(buf: &Buffer) -> String {
    let (w, h) = (buf.area.width, buf.area.height);
    let (bg0, fg0) = ("#1e2127", "#d7dae0");
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0}\" height=\"{:.0}\" font-family=\"DejaVu Sans Mono, monospace\" font-size=\"14\">",
        f32::from(w) * CW,
        f32::from(h) * CH
    );
    let _ = writeln!(out, "<rect width=\"100%\" height=\"100%\" fill=\"{bg0}\"/>");
    for y in 0..h {
        for x in 0..w {
            let c = &buf[(x, y)];
            let reversed = c.modifier.contains(Modifier::REVERSED);
            let (mut fg, mut bg) = (hex(c.fg, fg0), hex(c.bg, bg0));
            if reversed {
                std::mem::swap(&mut fg, &mut bg);
            }
            if bg != bg0 {
                let _ = writeln!(
                    out,
                    "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"{CW}\" height=\"{CH}\" fill=\"{bg}\"/>",
                    f32::from(x) * CW,
                    f32::from(y) * CH
                );
            }
            let sym = c.symbol();
            if sym.trim().is_empty() {
                continue;
            }
            let weight = if c.modifier.contains(Modifier::BOLD) {
                " font-weight=\"bold\""
            } else {
                ""
            };
            let deco = if c.modifier.contains(Modifier::UNDERLINED) {
                " text-decoration=\"underline\""
            } else {
                ""
            };
            let _ = writeln!(
                out,
                "<text x=\"{:.1}\" y=\"{:.1}\" fill=\"{fg}\"{weight}{deco}>{}</text>",
                f32::from(x) * CW,
                f32::from(y) * CH + 13.0,
                esc(sym)
            );
        }
    }
    out.push_str("</svg>\n");
    out
}

/// The SVG as a PNG image, drawn by resvg with the system's monospace fonts.
pub fn svg_to_png(svg: &str) -> Result<Vec<u8>, String> {
    let mut opt = resvg::usvg::Options::default();
    opt.fontdb_mut().load_system_fonts();
    let tree = resvg::usvg::Tree::from_str(svg, &opt)
        .map_err(|e| format!("the SVG does not parse: {e}"))?;
    let size = tree.size().to_int_size();
    let mut pixmap =
        resvg::tiny_skia::Pixmap::new(size.width(), size.height()).ok_or("the image is empty")?;
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::default(),
        &mut pixmap.as_mut(),
    );
    pixmap
        .encode_png()
        .map_err(|e| format!("PNG encoding: {e}"))
}
