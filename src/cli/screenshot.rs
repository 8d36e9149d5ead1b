//! `btx screenshot`: Render a scripted scene of the explorer's demo to an SVG or PNG file.

use super::*;

#[derive(clap::Args)]
pub struct Args {
    /// failure, framed, answer, finder or help.
    #[arg(long, value_name = "SCENE")]
    pub demo: String,
    #[arg(long, value_name = "FILE.svg|FILE.png")]
    pub out: PathBuf,
    /// Columns, 20 to 1000.
    #[arg(long, default_value_t = 110, value_parser = clap::value_parser!(u16).range(20..=1000))]
    pub width: u16,
    /// Rows, 5 to 500.
    #[arg(long, default_value_t = 34, value_parser = clap::value_parser!(u16).range(5..=500))]
    pub height: u16,
}

pub fn run(args: Args) -> Result<(), Failure> {
    let Args {
        demo,
        out,
        width,
        height,
    } = args;
    let app = btx::tui::scene(&demo).map_err(Failure::Plain)?;
    let buf = btx::tui::render(&app, width, height);
    match out.extension().and_then(|e| e.to_str()) {
        Some("svg") => std::fs::write(&out, btx::tui::svg::buffer_to_svg(&buf))
            .map_err(|e| Failure::Plain(format!("{}: {e}", btx::text::path(&out))))?,
        Some("png") => {
            let png = btx::tui::svg::svg_to_png(&btx::tui::svg::buffer_to_svg(&buf))
                .map_err(Failure::Plain)?;
            std::fs::write(&out, png)
                .map_err(|e| Failure::Plain(format!("{}: {e}", btx::text::path(&out))))?
        }
        _ => fail!(
            "{}: a screenshot is a .svg or a .png file",
            btx::text::path(&out)
        ),
    }
    Ok(())
}
