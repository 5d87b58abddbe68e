//! A film whose thickness comes from a greyscale image (`thickness_nm = { texture = … }`,
//! `material::film::ThicknessTexture`, issue 41):
//!
//! - **colour**: a texture of two flat halves (200 nm and 450 nm of water, n = 1.333) seen at
//!   normal incidence against a D65 emitter renders, half by half, the colour of the
//!   interference chart (`prisma fresnel --film-colours`, the analytic reference of
//!   `tests/soap_film.rs`) at each thickness, and the same pixels as a constant film of that
//!   thickness rendered with the same seed;
//! - **bad input**: a missing file, a file that is not an image, a colour image, min > max, a
//!   negative thickness, missing fields: one line naming the scene file and the field (and the
//!   texture file), exit code 2, no output file;
//! - **digest**: editing the texture changes the scene digest (parts cannot merge across it).

mod film_chart;

use std::path::Path;
use std::process::Command;

/// Writes a 16-bit greyscale PNG, `width` × `height`, whose left `split` columns have level
/// `left` and the rest `right`.
fn halves_png(path: &Path, width: u32, height: u32, split: u32, (left, right): (u16, u16)) {
    let levels: Vec<u16> =
        (0..height).flat_map(|_| (0..width).map(move |i| if i < split { left } else { right })).collect();
    image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_raw(width, height, levels)
        .expect("the buffer fits")
        .save(path)
        .expect("the PNG is written");
}

/// The scene of `tests/soap_film.rs`'s colour test: the camera at z = −10 looks along +z at the
/// film on z = 0 through a 1° view (cos θ ≥ 0.99996, 8 × 8 pixels, 256 spp), a D65 emitter behind
/// it; `material` is the film's (or a mirror's) body.
fn colour_scene(material: &str) -> String {
    format!(
        "background = 0\n[camera]\nposition = [0, 0, -10]\nlook_at = [0, 0, 0]\nfov_y_deg = 1\nwidth = 8\nheight = 8\n\
         [render]\nspp = 256\nmax_depth = 4\nprune_below = 0\n[materials.film]\n{material}\n\
         [[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 0, -1]\nmaterial = \"film\"\n\
         [[lights]]\ntype = \"quad\"\ncorner = [-5000, -5000, -20]\nedge1 = [10000, 0, 0]\nedge2 = [0, 10000, 0]\n\
         radiance = {{ illuminant = \"D65\" }}\nemit = \"edge1_cross_edge2\"\n"
    )
}

/// The rendered XYZ of every pixel of `scene_text` (the scene file at `path`), row by row.
fn render_pixels(scene_text: &str, path: &Path) -> Vec<[f64; 3]> {
    let scene = prisma::scene::parse(scene_text, path).expect("the scene loads");
    let job = prisma::render::Job { threads: 2, ..prisma::render::Job::new(scene.settings.clone()) };
    let image = prisma::render::render(&scene, &job).expect("renders").0;
    image.xyz().iter().map(|p| [f64::from(p.x), f64::from(p.y), f64::from(p.z)]).collect()
}

/// The mean XYZ over the image columns `columns` (8 pixels wide).
fn mean_over(pixels: &[[f64; 3]], columns: std::ops::Range<usize>) -> [f64; 3] {
    let chosen: Vec<&[f64; 3]> =
        pixels.iter().enumerate().filter(|(i, _)| columns.contains(&(i % 8))).map(|(_, p)| p).collect();
    let count = chosen.len() as f64;
    chosen
        .iter()
        .fold([0.0; 3], |sum, p| [sum[0] + p[0] / count, sum[1] + p[1] / count, sum[2] + p[2] / count])
}

#[test]
fn two_flat_halves_render_the_chart_colour_of_each_thickness() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let chart = film_chart::water_film_chart(dir.path());
    // Levels / 65535 × 655.35 nm = levels / 100 nm: 200 nm on the texture's left half, 450 nm
    // on its right (to f32 rounding, < 1e-4 nm).
    halves_png(&dir.path().join("halves.png"), 64, 8, 32, (20_000, 45_000));
    let scene_path = dir.path().join("scene.toml");
    // The image on the square [−0.1, 0.1]² of z = 0; the view spans ±0.087. The halves blend
    // only between the two middle columns' centres, |x| < 0.0016, inside image columns 3 and 4.
    let textured = colour_scene(
        "type = \"film\"\nior = 1.333\nthickness_nm = { texture = \"halves.png\", min = 0, max = 655.35, \
         corner = [-0.1, -0.1, 0], edge1 = [0.2, 0, 0], edge2 = [0, 0.2, 0] }",
    );
    let pixels = render_pixels(&textured, &scene_path);
    let white = mean_over(&render_pixels(&colour_scene("type = \"mirror\""), &scene_path), 0..8)[1];
    assert!(white.is_finite() && white > 0.0, "the mirror shows the emitter: Y = {white}");
    // The camera has world +x on the image's left (`camera::pinhole`, Mitsuba's handedness):
    // the texture's left half (x < 0, 200 nm) is the image's right, columns 5–7.
    for (thickness, columns) in [(200usize, 5..8), (450, 0..3)] {
        let seen = mean_over(&pixels, columns.clone()).map(|v| v / white);
        let row = chart[thickness];
        assert_eq!(row[0], thickness as f64);
        // As in tests/soap_film.rs: relative to the chart's brightest Y (7.8 %), the worst
        // there 1.4·10⁻⁴ (the render's wavelength sampling against 1 nm quadrature).
        let error = (0..3).map(|k| (seen[k] - row[k + 1]).abs()).fold(0.0, f64::max) / 0.078;
        eprintln!("{thickness} nm: textured half XYZ {seen:?}, chart {:?}, error {error:.2e}", &row[1..]);
        assert!(error < 1e-3, "{thickness} nm: {seen:?} against the chart's {:?}", &row[1..]);
        // The constant film of that thickness, same seed: the same samples, pixel by pixel;
        // only the texture's f32 rounding of the thickness (< 1e-4 nm) differs.
        let constant = render_pixels(
            &colour_scene(&format!("type = \"film\"\nior = 1.333\nthickness_nm = {thickness}")),
            &scene_path,
        );
        for (i, (a, b)) in
            pixels.iter().zip(&constant).enumerate().filter(|(i, _)| columns.contains(&(i % 8)))
        {
            for k in 0..3 {
                assert!((a[k] - b[k]).abs() / white < 1e-5, "pixel {i}: {a:?} vs constant {b:?}");
            }
        }
    }
    // And the two halves differ (200 nm is a yellow-brown, 450 nm a blue-green: the colours
    // differ by far more than the tolerances above).
    let (left, right) = (mean_over(&pixels, 0..3), mean_over(&pixels, 5..8));
    assert!((0..3).any(|k| (left[k] - right[k]).abs() / white > 0.01), "{left:?} {right:?}");
}

/// The `[materials.film]` of a textured film with `fields` after `texture = "…"`.
fn textured_scene(texture: &str, fields: &str) -> String {
    colour_scene(&format!("type = \"film\"\nthickness_nm = {{ texture = \"{texture}\", {fields} }}"))
        .replace("spp = 256", "spp = 1")
}

const FRAME: &str = "corner = [-1, -1, 0], edge1 = [2, 0, 0], edge2 = [0, 2, 0]";

/// Runs `prisma render` on `scene_text` in `dir`; asserts exit 2, one line naming the scene file
/// and every fragment, no output.
fn assert_rejected(dir: &Path, scene_text: &str, fragments: &[&str]) {
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, scene_text).expect("the scene is written");
    let out = dir.join("out");
    let output = Command::new(env!("CARGO_BIN_EXE_prisma"))
        .arg("render")
        .arg(&scene)
        .arg("-o")
        .arg(out.join("image.exr"))
        .arg("--quiet")
        .output()
        .expect("prisma runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{fragments:?}: {stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "not one line: {stderr}");
    assert!(stderr.contains("scene.toml"), "{stderr}");
    for fragment in fragments {
        assert!(stderr.contains(fragment), "missing {fragment:?} in: {stderr}");
    }
    assert!(
        !out.exists() || std::fs::read_dir(&out).map_or(0, |d| d.count()) == 0,
        "output written: {stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn bad_textures_are_one_line_errors() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let path = dir.path();
    halves_png(&path.join("good.png"), 4, 4, 2, (0, 65535));
    std::fs::write(path.join("text.png"), "not an image").expect("written");
    image::RgbImage::new(2, 2).save(path.join("colour.png")).expect("written");
    let field = "materials.film.thickness_nm";
    let cases: [(&str, String, Vec<&str>); 8] = [
        (
            "missing",
            textured_scene("absent.png", &format!("min = 100, max = 900, {FRAME}")),
            vec!["absent.png", field],
        ),
        (
            "not an image",
            textured_scene("text.png", &format!("min = 100, max = 900, {FRAME}")),
            vec!["text.png", field],
        ),
        (
            "colour",
            textured_scene("colour.png", &format!("min = 100, max = 900, {FRAME}")),
            vec!["colour.png", "greyscale"],
        ),
        (
            "min > max",
            textured_scene("good.png", &format!("min = 900, max = 100, {FRAME}")),
            vec!["thickness_nm.min", "max"],
        ),
        (
            "negative",
            textured_scene("good.png", &format!("min = -5, max = 100, {FRAME}")),
            vec!["thickness_nm.min", "-5"],
        ),
        (
            "absurd",
            textured_scene("good.png", &format!("min = 5, max = 1e9, {FRAME}")),
            vec!["thickness_nm.max"],
        ),
        ("missing fields", textured_scene("good.png", "min = 100, max = 900"), vec![field, "edge1"]),
        (
            "parallel edges",
            textured_scene(
                "good.png",
                "min = 1, max = 9, corner = [0, 0, 0], edge1 = [1, 0, 0], edge2 = [2, 0, 0]",
            ),
            vec!["thickness_nm.edge2", "parallel"],
        ),
    ];
    for (name, text, fragments) in &cases {
        eprintln!("{name}");
        assert_rejected(path, text, fragments);
    }
    // The good texture in the same frame loads.
    let good = textured_scene("good.png", &format!("min = 100, max = 900, {FRAME}"));
    prisma::scene::parse(&good, &path.join("scene.toml")).expect("the good texture loads");
}

#[test]
fn an_edited_texture_changes_the_scene_digest() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let texture = dir.path().join("t.png");
    let scene_path = dir.path().join("scene.toml");
    let text = textured_scene("t.png", &format!("min = 100, max = 900, {FRAME}"));
    let digest = || prisma::scene::parse(&text, &scene_path).expect("the scene loads").digest;
    halves_png(&texture, 4, 4, 2, (0, 65535));
    let before = digest();
    assert_eq!(digest(), before, "the digest is a function of the inputs");
    halves_png(&texture, 4, 4, 2, (0, 65534));
    assert_ne!(digest(), before, "one grey level changed");
}
