//! A map of a quantity in colour with its legend, as 8-bit RGB: the image through a perceptual
//! colour map (viridis's ramp, van der Walt and Smith 2015, by five of its stops), and at its
//! right a bar from 0 to the maximum, labelled in a 3 x 5 pixel font with the unit.

/// Five stops of viridis, dark to light.
const STOPS: [[f32; 3]; 5] = [
    [68.0, 1.0, 84.0],
    [59.0, 82.0, 139.0],
    [33.0, 145.0, 140.0],
    [94.0, 201.0, 98.0],
    [253.0, 231.0, 37.0],
];

/// The colour of `t` in [0, 1].
fn colour(t: f32) -> [u8; 3] {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (STOPS.len() - 1) as f32;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - i as f32;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    [0, 1, 2].map(|c| (a[c] + (b[c] - a[c]) * f).round() as u8)
}

/// The glyph of a character of the labels, rows of 3 bits from the top; a space for others.
fn glyph(c: char) -> [u8; 5] {
    match c {
        '0' => [0b111, 0b101, 0b101, 0b101, 0b111],
        '1' => [0b010, 0b110, 0b010, 0b010, 0b111],
        '2' => [0b111, 0b001, 0b111, 0b100, 0b111],
        '3' => [0b111, 0b001, 0b111, 0b001, 0b111],
        '4' => [0b101, 0b101, 0b111, 0b001, 0b001],
        '5' => [0b111, 0b100, 0b111, 0b001, 0b111],
        '6' => [0b111, 0b100, 0b111, 0b101, 0b111],
        '7' => [0b111, 0b001, 0b010, 0b010, 0b010],
        '8' => [0b111, 0b101, 0b111, 0b101, 0b111],
        '9' => [0b111, 0b101, 0b111, 0b001, 0b111],
        '.' => [0b000, 0b000, 0b000, 0b000, 0b010],
        'h' => [0b100, 0b100, 0b111, 0b101, 0b101],
        _ => [0; 5],
    }
}

/// An RGB canvas.
struct Canvas {
    width: usize,
    height: usize,
    rgb: Vec<u8>,
}

impl Canvas {
    fn set(&mut self, x: usize, y: usize, c: [u8; 3]) {
        if x < self.width && y < self.height {
            let i = 3 * (y * self.width + x);
            self.rgb[i..i + 3].copy_from_slice(&c);
        }
    }

    /// `text` with its top left corner at `(x, y)`, each font pixel `scale` pixels wide.
    fn text(&mut self, x: usize, y: usize, text: &str, scale: usize, c: [u8; 3]) {
        for (k, ch) in text.chars().enumerate() {
            let g = glyph(ch);
            for (row, bits) in g.iter().enumerate() {
                for col in 0..3 {
                    if bits & (0b100 >> col) != 0 {
                        for dy in 0..scale {
                            for dx in 0..scale {
                                self.set(x + (4 * k + col) * scale + dx, y + row * scale + dy, c);
                            }
                        }
                    }
                }
            }
        }
    }
}

/// A label of `value` in `unit`: one decimal below 100, none above.
fn label(value: f32, unit: char) -> String {
    if value < 100.0 {
        format!("{value:.1}{unit}")
    } else {
        format!("{value:.0}{unit}")
    }
}

/// `values` (`width` x `height`, rows from the top) mapped from 0 to their maximum, with a
/// legend in `unit` at the right: `(width, height, rgb)` of the whole picture, for
/// [`crate::write_png_bytes`]. Values that are not finite take the colour of 0.
pub fn colour_map(
    values: &[f32],
    width: usize,
    height: usize,
    unit: char,
) -> (usize, usize, Vec<u8>) {
    let max = values
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0f32, f32::max);
    let scale = (height / 120).max(1);
    let labels = [max, max * 0.5, 0.0].map(|v| label(v, unit));
    let text_width = labels.iter().map(|l| l.len()).max().unwrap_or(0) * 4 * scale;
    let bar = 6 * scale;
    let legend = 4 * scale + bar + 2 * scale + text_width + 2 * scale;
    // Tall enough for three labels.
    let total_height = height.max(3 * 7 * scale);
    let mut canvas = Canvas {
        width: width + legend,
        height: total_height,
        rgb: vec![255; 3 * (width + legend) * total_height],
    };
    for y in 0..height {
        for x in 0..width {
            let v = values[y * width + x];
            canvas.set(x, y, colour(if max > 0.0 { v / max } else { 0.0 }));
        }
    }
    // The bar, top = max, bottom = 0, with the labels beside its top, middle and bottom.
    let (top, bottom) = (2 * scale, total_height - 2 * scale);
    let x0 = width + 4 * scale;
    for y in top..bottom {
        let t = 1.0 - (y - top) as f32 / (bottom - top - 1).max(1) as f32;
        for x in x0..x0 + bar {
            canvas.set(x, y, colour(t));
        }
    }
    let glyph_height = 5 * scale;
    let ys = [
        top,
        (top + bottom) / 2 - glyph_height / 2,
        bottom - glyph_height,
    ];
    for (l, y) in labels.iter().zip(ys) {
        canvas.text(x0 + bar + 2 * scale, y, l, scale, [0, 0, 0]);
    }
    (canvas.width, canvas.height, canvas.rgb)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_map_runs_dark_to_light_and_the_legend_sits_at_the_right() {
        let values: Vec<f32> = (0..40 * 30)
            .map(|i| (i % 40) as f32 / 39.0 * 12.0)
            .collect();
        let (w, h, rgb) = colour_map(&values, 40, 30, 'h');
        assert!(w > 40 && h >= 30 && rgb.len() == 3 * w * h);
        let at = |x: usize, y: usize| {
            let i = 3 * (y * w + x);
            [rgb[i], rgb[i + 1], rgb[i + 2]]
        };
        assert_eq!(at(0, 0), [68, 1, 84]);
        assert_eq!(at(39, 10), [253, 231, 37]);
        // The bar's top is the maximum's colour, its bottom the minimum's.
        assert_eq!(at(44, 2), [253, 231, 37]);
        assert_eq!(at(44, h - 3), [68, 1, 84]);
        // Some label pixels are black.
        assert!((0..h).any(|y| (40..w).any(|x| at(x, y) == [0, 0, 0])));
        assert_eq!(label(12.0, 'h'), "12.0h");
        assert_eq!(label(4380.0, 'h'), "4380h");
    }
}
