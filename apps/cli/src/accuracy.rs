//! The comparison math of `phosphor accuracy`: error statistics of an image against the
//! reference, the false-colour heat-map, and the median of frame times.
//!
//! All comparisons are per channel, on the framebuffer's linear values and on the codes the
//! scene's encoding displays, over the pixels the reference covers.

use phosphor_math::glam::Vec3;
use phosphor_raster::Encoding;
use phosphor_raster::encode::srgb_encode;

use crate::font;
use crate::rgb8::Rgb8Image;

/// Width of the heat-map's scale bar, in pixels.
const BAR_WIDTH: u32 = 12;
/// Gap between the image and the scale bar, in pixels.
const BAR_GAP: u32 = 4;

/// How far an image is from the reference, over the pixels the reference covers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorStats {
    /// Root mean square of the per-channel differences (linear values).
    pub rmse: f64,
    /// Peak signal-to-noise ratio for a peak of 1, in dB: `20 log10(1 / rmse)`; infinite when
    /// the images are equal.
    pub psnr_db: f64,
    /// Largest per-channel absolute difference (linear values).
    pub max_abs: f64,
    /// Largest per-channel difference in displayed 8-bit codes: both values encoded as the
    /// scene displays them (sRGB or linear, before rounding), times 255.
    pub max_codes: f64,
    /// Share (0..=1) of the covered pixels where some channel differs by more than one
    /// displayed code.
    pub share_over_code: f64,
    /// Pixels compared (covered by the reference).
    pub covered: usize,
}

/// The largest per-channel absolute difference of two colours.
#[must_use]
pub fn pixel_error(a: Vec3, b: Vec3) -> f32 {
    (a - b).abs().max_element()
}

/// A linear value as the display shows it, in codes (0..=255, not rounded).
#[must_use]
pub fn displayed_code(value: f32, encoding: Encoding) -> f64 {
    let v = if value.is_nan() {
        0.0
    } else {
        value.clamp(0.0, 1.0)
    };
    f64::from(match encoding {
        Encoding::Srgb => srgb_encode(v),
        Encoding::Linear => v,
    }) * 255.0
}

/// Compares `image` with `reference` (same size, row-major) over the pixels where `covered` is
/// true (every pixel when `None`: a background pixel is the same clear colour in both and
/// would only dilute the figures). `None` when the sizes differ or nothing is compared.
/// Non-finite values count as the largest error (1, 255 codes).
#[must_use]
pub fn compare(
    image: &[Vec3],
    reference: &[Vec3],
    covered: Option<&[bool]>,
    encoding: Encoding,
) -> Option<ErrorStats> {
    if image.len() != reference.len() || covered.is_some_and(|c| c.len() != image.len()) {
        return None;
    }
    let mut sum_sq = 0.0f64;
    let mut max_abs = 0.0f64;
    let mut max_codes = 0.0f64;
    let mut over = 0usize;
    let mut count = 0usize;
    for (i, (&a, &b)) in image.iter().zip(reference).enumerate() {
        if covered.is_some_and(|c| !c[i]) {
            continue;
        }
        count += 1;
        let mut pixel_max = 0.0f64;
        let mut pixel_codes = 0.0f64;
        for c in 0..3 {
            let d = f64::from(a[c]) - f64::from(b[c]);
            let (d, codes) = if d.is_finite() {
                (
                    d.abs().min(1.0),
                    (displayed_code(a[c], encoding) - displayed_code(b[c], encoding)).abs(),
                )
            } else {
                (1.0, 255.0)
            };
            sum_sq += d * d;
            pixel_max = pixel_max.max(d);
            pixel_codes = pixel_codes.max(codes);
        }
        max_abs = max_abs.max(pixel_max);
        max_codes = max_codes.max(pixel_codes);
        if pixel_codes > 1.0 {
            over += 1;
        }
    }
    if count == 0 {
        return None;
    }
    let rmse = (sum_sq / (count * 3) as f64).sqrt();
    let psnr_db = if rmse > 0.0 {
        20.0 * (1.0 / rmse).log10()
    } else {
        f64::INFINITY
    };
    Some(ErrorStats {
        rmse,
        psnr_db,
        max_abs,
        max_codes,
        share_over_code: over as f64 / count as f64,
        covered: count,
    })
}

/// Minimum, median and maximum of `values` (0s when empty).
#[must_use]
pub fn spread(values: &[f64]) -> (f64, f64, f64) {
    let min = values.iter().copied().fold(f64::INFINITY, f64::min);
    let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if values.is_empty() {
        (0.0, 0.0, 0.0)
    } else {
        (min, median(values), max)
    }
}

/// The median of `values` (the mean of the middle two for an even count); 0 when empty.
#[must_use]
pub fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    match n {
        0 => 0.0,
        _ if n % 2 == 1 => sorted[n / 2],
        _ => 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]),
    }
}

/// False colour for `t` in [0, 1]: black, purple, red, orange, yellow, white.
/// Out-of-range and non-finite values saturate (NaN reads as the top of the scale).
#[must_use]
pub fn heat_colour(t: f32) -> [u8; 3] {
    const STOPS: [[f32; 3]; 6] = [
        [0.0, 0.0, 0.0],
        [60.0, 0.0, 140.0],
        [190.0, 0.0, 110.0],
        [255.0, 90.0, 0.0],
        [255.0, 220.0, 0.0],
        [255.0, 255.0, 255.0],
    ];
    let t = if t.is_nan() { 1.0 } else { t.clamp(0.0, 1.0) };
    let x = t * (STOPS.len() - 1) as f32;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - i as f32;
    let mut out = [0u8; 3];
    for c in 0..3 {
        let v = STOPS[i][c] + (STOPS[i + 1][c] - STOPS[i][c]) * f;
        out[c] = v.round().clamp(0.0, 255.0) as u8;
    }
    out
}

/// The error heat-map of `image` against `reference` (`width` x `height`): each pixel's largest
/// channel error mapped through [`heat_colour`] over `[0, scale]`, with a scale bar on the right
/// (bottom = 0, top = `scale`, white ticks at quarters). `None` if the sizes do not match.
#[must_use]
pub fn heat_map(
    image: &[Vec3],
    reference: &[Vec3],
    width: u32,
    height: u32,
    scale: f32,
) -> Option<Rgb8Image> {
    let pixels = (width as usize).checked_mul(height as usize)?;
    if image.len() != pixels || reference.len() != pixels {
        return None;
    }
    let scale = if scale.is_finite() && scale > 0.0 {
        scale
    } else {
        1.0
    };
    scale_bar_image(width, height, |i| {
        heat_colour(pixel_error(image[i], reference[i]) / scale)
    })
}

/// A `width` x `height` false-colour image whose pixel `i` (row-major) is `colour_of(i)`, with
/// [`heat_map`]'s scale bar on the right (bottom = 0, top = the scale, white ticks at quarters;
/// [`with_scale_labels`] writes the numbers). `None` for an empty image.
#[must_use]
pub fn scale_bar_image(
    width: u32,
    height: u32,
    colour_of: impl Fn(usize) -> [u8; 3],
) -> Option<Rgb8Image> {
    if (width as usize).checked_mul(height as usize)? == 0 {
        return None;
    }
    let out_width = width + BAR_GAP + BAR_WIDTH;
    let mut data = vec![0u8; out_width as usize * height as usize * 3];
    for y in 0..height {
        let row = y as usize * out_width as usize;
        for x in 0..width {
            let colour = colour_of((y * width + x) as usize);
            let o = (row + x as usize) * 3;
            data[o..o + 3].copy_from_slice(&colour);
        }
        // The bar: the colour for the error at this height, ticks every quarter of the scale.
        let t = if height > 1 {
            1.0 - y as f32 / (height - 1) as f32
        } else {
            1.0
        };
        let quarter = (t * 4.0).round() / 4.0;
        let is_tick = ((t - quarter) * (height.max(2) - 1) as f32).abs() < 0.5;
        for x in 0..BAR_WIDTH {
            let colour = if is_tick && !(3..BAR_WIDTH - 3).contains(&x) {
                [255, 255, 255]
            } else {
                heat_colour(t)
            };
            let o = (row + (width + BAR_GAP + x) as usize) * 3;
            data[o..o + 3].copy_from_slice(&colour);
        }
    }
    Some(Rgb8Image {
        width: out_width,
        height,
        data,
    })
}

/// `map` (from [`heat_map`]) widened on the right with the scale bar's numbers: the error at
/// each quarter tick, white on black, at a text size that suits the image's height (none when
/// the image is too small to hold them).
#[must_use]
pub fn with_scale_labels(map: &Rgb8Image, scale: f32) -> Rgb8Image {
    let text = if map.height >= 400 { 2 } else { 1 };
    let labels: Vec<String> = (0..=4)
        .map(|q| format!("{:.3}", scale * q as f32 / 4.0))
        .collect();
    let widest = labels
        .iter()
        .map(|l| font::text_width(l, text))
        .max()
        .unwrap_or(0);
    let margin = widest + 4 * text;
    let width = map.width + margin;
    let mut out = Rgb8Image {
        width,
        height: map.height,
        data: vec![0; width as usize * map.height as usize * 3],
    };
    for y in 0..map.height as usize {
        let src = y * map.width as usize * 3;
        let dst = y * width as usize * 3;
        out.data[dst..dst + map.width as usize * 3]
            .copy_from_slice(&map.data[src..src + map.width as usize * 3]);
    }
    let th = font::text_height(text);
    if map.height < 5 * th {
        return out;
    }
    for (q, label) in labels.iter().enumerate() {
        // The tick rows of heat_map's bar: t = q / 4 at y = (1 - t) (height - 1).
        let tick_y = ((1.0 - q as f32 / 4.0) * (map.height - 1) as f32).round() as i64;
        let y = (tick_y - i64::from(th / 2)).clamp(0, i64::from(map.height - th));
        font::draw_text(
            &mut out,
            i64::from(map.width + 2 * text),
            y,
            label,
            text,
            [255, 255, 255],
        );
    }
    out
}

/// `img` with `title` written above it on a black band (the heat-maps' title: what is shown
/// and in which units), at the text size [`with_scale_labels`] picks for its height.
#[must_use]
pub fn with_title(img: &Rgb8Image, title: &str) -> Rgb8Image {
    let text = if img.height >= 400 { 2 } else { 1 };
    let band = font::text_height(text) + 6 * text;
    let width = img.width.max(font::text_width(title, text) + 4 * text);
    let mut out = Rgb8Image {
        width,
        height: img.height + band,
        data: vec![0; width as usize * (img.height + band) as usize * 3],
    };
    for y in 0..img.height as usize {
        let src = y * img.width as usize * 3;
        let dst = (y + band as usize) * width as usize * 3;
        out.data[dst..dst + img.width as usize * 3]
            .copy_from_slice(&img.data[src..src + img.width as usize * 3]);
    }
    font::draw_text(
        &mut out,
        i64::from(2 * text),
        i64::from(3 * text),
        title,
        text,
        [255, 255, 255],
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_images_have_zero_error_and_infinite_psnr() {
        let img = vec![Vec3::new(0.2, 0.4, 0.6); 12];
        let s = compare(&img, &img, None, Encoding::Srgb).expect("same size");
        assert_eq!(s.rmse, 0.0);
        assert_eq!(s.max_abs, 0.0);
        assert_eq!(s.max_codes, 0.0);
        assert_eq!(s.share_over_code, 0.0);
        assert!(s.psnr_db.is_infinite());
    }

    #[test]
    fn rmse_psnr_and_max_follow_their_definitions() {
        // One pixel off by 0.1 in red only, three exact: mean square = 0.01 / 12.
        let reference = vec![Vec3::ZERO; 4];
        let mut image = reference.clone();
        image[1] = Vec3::new(0.1, 0.0, 0.0);
        let s = compare(&image, &reference, None, Encoding::Linear).expect("same size");
        let rmse = (0.01f64 / 12.0).sqrt();
        assert!((s.rmse - rmse).abs() < 1e-7, "{}", s.rmse);
        assert!((s.psnr_db - 20.0 * (1.0 / rmse).log10()).abs() < 1e-4);
        assert!((s.max_abs - 0.1).abs() < 1e-6);
        assert!((s.max_codes - 25.5).abs() < 1e-4, "{}", s.max_codes);
        assert!((s.share_over_code - 0.25).abs() < 1e-12);
        // Over the one covered pixel only: the background no longer dilutes the share.
        let covered = [false, true, false, false];
        let s = compare(&image, &reference, Some(&covered), Encoding::Linear).expect("covered");
        assert_eq!(s.covered, 1);
        assert!((s.share_over_code - 1.0).abs() < 1e-12);
        assert!((s.rmse - (0.01f64 / 3.0).sqrt()).abs() < 1e-7);
        // In sRGB, 0.1 above black is 89 codes (the curve is steep near 0).
        let s = compare(&image, &reference, None, Encoding::Srgb).expect("same size");
        assert!((s.max_codes - f64::from(srgb_encode(0.1)) * 255.0).abs() < 1e-3);
    }

    #[test]
    fn errors_of_one_lsb_or_less_are_not_counted_as_visible() {
        let reference = vec![Vec3::splat(0.5); 2];
        let image = vec![
            Vec3::splat(0.5 + 0.9 / 255.0),
            Vec3::splat(0.5 + 1.5 / 255.0),
        ];
        let s = compare(&image, &reference, None, Encoding::Linear).expect("same size");
        assert!((s.share_over_code - 0.5).abs() < 1e-12);
    }

    #[test]
    fn mismatched_or_empty_images_are_not_compared() {
        assert!(compare(&[Vec3::ZERO], &[], None, Encoding::Srgb).is_none());
        assert!(compare(&[], &[], None, Encoding::Srgb).is_none());
        let none = [false];
        assert!(compare(&[Vec3::ZERO], &[Vec3::ONE], Some(&none), Encoding::Srgb).is_none());
    }

    #[test]
    fn non_finite_pixels_count_as_the_largest_error() {
        let s = compare(
            &[Vec3::new(f32::NAN, 0.0, 0.0)],
            &[Vec3::ZERO],
            None,
            Encoding::Srgb,
        )
        .expect("same size");
        assert!(s.rmse.is_finite() && s.max_abs == 1.0 && s.max_codes == 255.0);
    }

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        assert_eq!(median(&[]), 0.0);
        assert_eq!(spread(&[3.0, 1.0, 2.0, 9.0]), (1.0, 2.5, 9.0));
        assert_eq!(spread(&[]), (0.0, 0.0, 0.0));
    }

    #[test]
    fn heat_colour_runs_from_black_to_white_and_saturates() {
        assert_eq!(heat_colour(0.0), [0, 0, 0]);
        assert_eq!(heat_colour(1.0), [255, 255, 255]);
        assert_eq!(heat_colour(7.0), [255, 255, 255]);
        assert_eq!(heat_colour(-1.0), [0, 0, 0]);
        assert_eq!(heat_colour(f32::NAN), [255, 255, 255]);
    }

    #[test]
    fn heat_map_marks_errors_and_carries_a_scale_bar() {
        let reference = vec![Vec3::ZERO; 6];
        let mut image = reference.clone();
        image[4] = Vec3::splat(0.5); // (x 1, y 1) in a 3x2 image
        let map = heat_map(&image, &reference, 3, 2, 0.5).expect("sizes match");
        assert_eq!(map.width, 3 + BAR_GAP + BAR_WIDTH);
        assert_eq!(map.data.len(), (map.width * map.height * 3) as usize);
        let at = |x: u32, y: u32| {
            let o = ((y * map.width + x) * 3) as usize;
            [map.data[o], map.data[o + 1], map.data[o + 2]]
        };
        assert_eq!(at(0, 0), [0, 0, 0]);
        assert_eq!(at(1, 1), [255, 255, 255]);
        // Bar centre column: top is the top of the scale, bottom is zero.
        let bar_x = 3 + BAR_GAP + BAR_WIDTH / 2;
        assert_eq!(at(bar_x, 0), heat_colour(1.0));
        assert_eq!(at(bar_x, 1), heat_colour(0.0));
        assert!(heat_map(&image, &reference, 4, 2, 0.5).is_none());
    }

    #[test]
    fn scale_labels_widen_the_map_and_keep_it() {
        let reference = vec![Vec3::ZERO; 100 * 60];
        let map = heat_map(&reference, &reference, 100, 60, 0.1).expect("sizes match");
        let labelled = with_scale_labels(&map, 0.1);
        assert_eq!(labelled.height, map.height);
        assert!(labelled.width > map.width);
        let row = |img: &Rgb8Image, y: usize| {
            img.data[y * img.width as usize * 3..][..map.width as usize * 3].to_vec()
        };
        assert_eq!(row(&labelled, 30), row(&map, 30));
        // Numbers were written in the margin.
        let margin_lit = (0..labelled.height as usize).any(|y| {
            (map.width as usize..labelled.width as usize)
                .any(|x| labelled.data[(y * labelled.width as usize + x) * 3] == 255)
        });
        assert!(margin_lit);
        // A title band on top, the map below it unchanged.
        let titled = with_title(&labelled, "error");
        assert!(titled.height > labelled.height);
        let band = (titled.height - labelled.height) as usize;
        assert_eq!(
            titled.data[band * titled.width as usize * 3..][..labelled.width as usize * 3],
            labelled.data[..labelled.width as usize * 3]
        );
        assert!(titled.data[..band * titled.width as usize * 3].contains(&255));
    }
}
