//! Figures as SVG text and PNG bytes, drawn by plotters. PNG text needs a font file: DejaVu Sans
//! is compiled in (assets/fonts/, with its licence), so a machine without fonts draws the same
//! figure. Call [`register_font`] before drawing any text with plotters (the examples do too).

use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::{Error, Result};

static FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// Registers the compiled-in DejaVu Sans as plotters' "sans-serif" (the family every figure of
/// the project names), once per process.
pub fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        if plotters::style::register_font("sans-serif", FontStyle::Normal, FONT).is_err() {
            unreachable!("the compiled-in DejaVu Sans parses");
        }
    });
}

/// What a drawing function returns.
pub type Drawn = std::result::Result<(), Box<dyn std::error::Error>>;
/// A drawing function on an SVG canvas.
pub type DrawSvg<'a> = &'a dyn for<'b> Fn(&DrawingArea<SVGBackend<'b>, Shift>) -> Drawn;
/// A drawing function on a bitmap canvas.
pub type DrawPng<'a> = &'a dyn for<'b> Fn(&DrawingArea<BitMapBackend<'b>, Shift>) -> Drawn;

fn failed(e: impl std::fmt::Display) -> Error {
    Error::run(format!("cannot draw the figure ({e})"))
}

/// The figure `draw` makes, as SVG text of `size` pixels.
pub fn svg(size: (u32, u32), draw: DrawSvg) -> Result<String> {
    register_font();
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
        draw(&root).map_err(failed)?;
        root.present().map_err(failed)?;
    }
    Ok(text)
}

/// The figure `draw` makes, as PNG bytes of `size` pixels (8-bit RGB).
pub fn png(size: (u32, u32), draw: DrawPng) -> Result<Vec<u8>> {
    register_font();
    let mut pixels = vec![255u8; 3 * size.0 as usize * size.1 as usize];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, size).into_drawing_area();
        draw(&root).map_err(failed)?;
        root.present().map_err(failed)?;
    }
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, size.0, size.1);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(failed)?;
    writer.write_image_data(&pixels).map_err(failed)?;
    writer.finish().map_err(failed)?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text_only<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>) -> Drawn
    where
        DB::ErrorType: 'static,
    {
        root.fill(&WHITE)?;
        root.draw(&Text::new("Fractum", (10, 10), ("sans-serif", 20)))?;
        Ok(())
    }

    #[test]
    fn png_draws_text_with_the_compiled_in_font_and_svg_names_it() {
        let bytes = png((120, 40), &|r| text_only(r)).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        let decoder = png::Decoder::new(std::io::Cursor::new(&bytes));
        let mut reader = decoder.read_info().unwrap();
        let mut pixels = vec![0; reader.output_buffer_size()];
        reader.next_frame(&mut pixels).unwrap();
        // The text put dark pixels on the white ground.
        let dark = pixels.chunks(3).filter(|p| p[0] < 128).count();
        assert!(dark > 50, "{dark} dark pixels");
        let text = svg((120, 40), &|r| text_only(r)).unwrap();
        assert!(
            text.contains(">\nFractum\n</text>") && text.contains("font-family=\"sans-serif\""),
            "{text}"
        );
    }
}
