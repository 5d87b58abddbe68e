//! Regressions of issue 37's output cases (../shared/cases/reliability-parts/, scripts 06, 07 and
//! 10): an output never replaces an input (however it is spelled), symbolic links are followed
//! as the kernel would follow them, a replaced output keeps its mode, `/dev/stdout` into a pipe
//! works, an interrupted render into a special file leaves no part beside it, a failed export
//! leaves no directory, and a FIFO given as a part is refused instead of read forever. Each test
//! runs the real binary and is named after what it pins.

mod cli;

use cli::{assert_refused, prisma, render, scene_dir, stderr};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

const SCENE: &str = "background = 0.5\n[camera]\nposition = [0, 0, -5]\nlook_at = [0, 0, 0]\nfov_y_deg = 40\nwidth = 16\nheight = 12\n[render]\nspp = 2\n";

/// A scene that loads `mesh_0.obj` beside it, moved and scaled (exported, the mesh changes).
const MESH_SCENE: &str = "[camera]\nposition = [0, 0, -5]\nlook_at = [0, 0, 0]\nfov_y_deg = 40\nwidth = 8\nheight = 6\n[materials.g]\ntype = \"dielectric\"\nior = 1.5\n[[shapes]]\ntype = \"mesh\"\nfile = \"mesh_0.obj\"\nscale = 2.0\nposition = [0.5, 0, 0]\nmaterial = \"g\"\n";
const MESH: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

/// The first four bytes of every OpenEXR file.
const EXR_MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];

fn text(path: &Path) -> String {
    path.to_string_lossy().into_owned()
}

/// Two parts of the scene in `dir` (samples 0..1 and 1..2 of 2): `a.exr` and `b.exr`.
fn two_parts(scene: &Path, dir: &Path) -> (PathBuf, PathBuf) {
    let (a, b) = (dir.join("a.exr"), dir.join("b.exr"));
    for (path, samples) in [(&a, "0..1"), (&b, "1..2")] {
        let output = render(
            scene,
            &["--samples", samples, "-o", &text(path), "--preview", &text(&path.with_extension("png"))],
        );
        assert!(output.status.success(), "{}", stderr(&output));
    }
    (a, b)
}

#[test]
fn stats_overwrites_scene_is_refused() {
    let (dir, scene) = scene_dir(SCENE);
    let exr = dir.path().join("o.exr");
    let output = render(&scene, &["-o", &text(&exr), "--stats", &text(&scene)]);
    assert_refused(&output, &["--stats", "scene.toml", "is the scene file"]);
    assert_eq!(std::fs::read_to_string(&scene).unwrap(), SCENE, "the scene is untouched");
    assert!(!exr.exists(), "refused before any work");
    // The preview onto the scene, through a symbolic link: the same file.
    let link = dir.path().join("link.png");
    std::os::unix::fs::symlink(&scene, &link).unwrap();
    let output = render(&scene, &["-o", &text(&exr), "--preview", &text(&link)]);
    assert_refused(&output, &["--preview", "is the scene file"]);
    assert_eq!(std::fs::read_to_string(&scene).unwrap(), SCENE);
}

#[test]
fn render_onto_a_mesh_the_scene_loads_is_refused() {
    let (dir, scene) = scene_dir(MESH_SCENE);
    let mesh = dir.path().join("mesh_0.obj");
    std::fs::write(&mesh, MESH).unwrap();
    let output = render(&scene, &["-o", &text(&dir.path().join("o.exr")), "--stats", &text(&mesh)]);
    assert_refused(&output, &["--stats", "mesh_0.obj", "a mesh the scene loads"]);
    assert_eq!(std::fs::read_to_string(&mesh).unwrap(), MESH);
}

/// A scene seen through a lens-system camera read from `singlet.dat` beside it.
const LENS_SCENE: &str = "background = 0.5\n[camera]\nposition = [0, 0, -5]\nlook_at = [0, 0, 0]\nlens = \"singlet.dat\"\nsensor_height_mm = 24\nwidth = 8\nheight = 6\n[render]\nspp = 1\n";

/// A soap film whose thickness is read from `thickness.png` beside the scene.
const TEXTURE_SCENE: &str = "background = 0.5\n[camera]\nposition = [0, 0, -5]\nlook_at = [0, 0, 0]\nfov_y_deg = 40\nwidth = 8\nheight = 6\n[render]\nspp = 1\n[materials.soap]\ntype = \"film\"\nior = 1.33\nthickness_nm = { texture = \"thickness.png\", min = 100, max = 900, corner = [-1, -1, 0], edge1 = [2, 0, 0], edge2 = [0, 2, 0] }\n[[shapes]]\ntype = \"quad\"\ncorner = [-1, -1, 0]\nedge1 = [2, 0, 0]\nedge2 = [0, 2, 0]\nmaterial = \"soap\"\n";

#[test]
fn render_onto_the_lens_file_the_scene_loads_is_refused() {
    let (dir, scene) = scene_dir(LENS_SCENE);
    let lens = dir.path().join("singlet.dat");
    let original =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("data/lenses/singlet_nbk7.dat")).unwrap();
    std::fs::write(&lens, &original).unwrap();
    let output = render(&scene, &["-o", &text(&dir.path().join("o.exr")), "--stats", &text(&lens)]);
    assert_refused(&output, &["--stats", "singlet.dat", "the lens file the scene loads"]);
    assert_eq!(std::fs::read(&lens).unwrap(), original);
}

#[test]
fn render_onto_a_texture_the_scene_loads_is_refused() {
    let (dir, scene) = scene_dir(TEXTURE_SCENE);
    let texture = dir.path().join("thickness.png");
    let original =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/soap_film_thickness.png")).unwrap();
    std::fs::write(&texture, &original).unwrap();
    let output = render(&scene, &["-o", &text(&dir.path().join("o.exr")), "--preview", &text(&texture)]);
    assert_refused(&output, &["--preview", "thickness.png", "a texture the scene loads"]);
    assert_eq!(std::fs::read(&texture).unwrap(), original);
}

#[test]
fn export_overwrites_the_scenes_own_mesh_is_refused() {
    let (dir, scene) = scene_dir(MESH_SCENE);
    let mesh = dir.path().join("mesh_0.obj");
    std::fs::write(&mesh, MESH).unwrap();
    let output = prisma().arg("export").arg(&scene).arg("-o").arg(dir.path()).output().unwrap();
    assert_refused(&output, &["mesh_0.obj", "a mesh the scene loads"]);
    assert_eq!(
        std::fs::read_to_string(&mesh).unwrap(),
        MESH,
        "the mesh is not replaced by its transformed copy"
    );
    assert!(!dir.path().join("spectra.json").exists(), "nothing was written");
}

#[test]
fn merge_onto_a_part_is_refused_through_any_link() {
    let (dir, scene) = scene_dir(SCENE);
    let (a, b) = two_parts(&scene, dir.path());
    let before = std::fs::read(&a).unwrap();
    let hard = dir.path().join("hard.exr");
    std::fs::hard_link(&a, &hard).unwrap();
    let soft = dir.path().join("soft.exr");
    std::os::unix::fs::symlink(&a, &soft).unwrap();
    for out in [&a, &hard, &soft] {
        let output = prisma().arg("merge").args([&a, &b]).arg("-o").arg(out).output().unwrap();
        assert_refused(&output, &[&format!("-o {}", out.display()), "is the part being merged"]);
        assert_eq!(std::fs::read(&a).unwrap(), before, "-o {}: the part is untouched", out.display());
    }
}

#[test]
fn resume_onto_its_own_part_is_refused() {
    let (dir, scene) = scene_dir(SCENE);
    let (a, _) = two_parts(&scene, dir.path());
    let before = std::fs::read(&a).unwrap();
    let output = render(
        &scene,
        &["--resume", &text(&a), "-o", &text(&a), "--preview", &text(&dir.path().join("r.png"))],
    );
    assert_refused(&output, &["-o", "a.exr", "is the part being resumed"]);
    assert_eq!(std::fs::read(&a).unwrap(), before);
}

/// Runs `command` for at most `limit`; kills it when it takes longer (returns `None`).
fn run_with_limit(mut command: Command, limit: Duration) -> Option<Output> {
    let mut child = command.stdout(Stdio::null()).stderr(Stdio::piped()).spawn().expect("prisma runs");
    let start = Instant::now();
    while start.elapsed() < limit {
        if child.try_wait().expect("wait").is_some() {
            return Some(child.wait_with_output().expect("output"));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let _ = child.kill();
    let _ = child.wait();
    None
}

fn mkfifo(path: &Path) {
    let status = Command::new("mkfifo").arg(path).status().expect("mkfifo runs");
    assert!(status.success(), "mkfifo {}", path.display());
}

#[test]
fn merging_a_fifo_blocks_forever_no_more() {
    let (dir, scene) = scene_dir(SCENE);
    let (a, _) = two_parts(&scene, dir.path());
    let fifo = dir.path().join("fifo.exr");
    mkfifo(&fifo);
    let mut merge = prisma();
    merge.arg("merge").arg(&a).arg(&fifo).arg("-o").arg(dir.path().join("m.exr"));
    let output = run_with_limit(merge, Duration::from_secs(20))
        .expect("merge returns instead of waiting for a writer");
    assert_refused(&output, &["fifo.exr", "FIFO", "not a regular file"]);

    let mut resume = prisma();
    resume
        .arg("render")
        .arg(&scene)
        .arg("--quiet")
        .arg("--resume")
        .arg(&fifo)
        .arg("-o")
        .arg(dir.path().join("r.exr"));
    let output = run_with_limit(resume, Duration::from_secs(20)).expect("--resume returns");
    assert_refused(&output, &["fifo.exr", "FIFO", "not a regular file"]);
}

/// Script 06: as root, another user's symbolic link in a sticky world-writable directory, aimed
/// at a root-owned 0600 file. The kernel (fs.protected_symlinks = 1) refuses root's `echo >`
/// through it; prisma must refuse too (whatever the sysctl says), and leave the file as it was.
#[test]
fn symlink_follow_bypasses_protected_symlinks() {
    use std::os::unix::fs::PermissionsExt;
    // SAFETY: geteuid has no preconditions.
    if unsafe { libc::geteuid() } != 0 {
        eprintln!(
            "skipped: symlink_follow_bypasses_protected_symlinks needs root (it chowns a link to nobody)"
        );
        return;
    }
    let (dir, scene) = scene_dir(SCENE);
    let secret = dir.path().join("config.txt");
    std::fs::write(&secret, "ROOT SECRET CONFIG\n").unwrap();
    std::fs::set_permissions(&secret, std::fs::Permissions::from_mode(0o600)).unwrap();
    let public = dir.path().join("public");
    std::fs::create_dir(&public).unwrap();
    std::fs::set_permissions(&public, std::fs::Permissions::from_mode(0o1777)).unwrap();
    let link = public.join("render_out.exr");
    std::os::unix::fs::symlink(&secret, &link).unwrap();
    // uid and gid 65534: `nobody`.
    std::os::unix::fs::lchown(&link, Some(65534), Some(65534)).unwrap();

    let output = render(&scene, &["-o", &text(&link), "--preview", &text(&dir.path().join("p.png"))]);
    assert_refused(&output, &["render_out.exr", "symbolic link", "protected_symlinks"]);
    assert_eq!(std::fs::read_to_string(&secret).unwrap(), "ROOT SECRET CONFIG\n");
    assert_eq!(std::fs::metadata(&secret).unwrap().permissions().mode() & 0o7777, 0o600);
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink(), "the link stays");

    // The same link owned by root (the follower) is followed: the file it names is replaced.
    std::os::unix::fs::lchown(&link, Some(0), Some(0)).unwrap();
    let output = render(&scene, &["-o", &text(&link), "--preview", &text(&dir.path().join("p.png"))]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(std::fs::read(&secret).unwrap()[..4], EXR_MAGIC);
}

#[test]
fn replacing_an_output_keeps_its_mode() {
    use std::os::unix::fs::PermissionsExt;
    let (dir, scene) = scene_dir(SCENE);
    let exr = dir.path().join("o.exr");
    let png = dir.path().join("o.png");
    let args = ["-o", &text(&exr)];
    assert!(render(&scene, &args).status.success());
    std::fs::set_permissions(&exr, std::fs::Permissions::from_mode(0o600)).unwrap();
    std::fs::set_permissions(&png, std::fs::Permissions::from_mode(0o640)).unwrap();
    let output = render(&scene, &args);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(
        std::fs::metadata(&exr).unwrap().permissions().mode() & 0o7777,
        0o600,
        "a private image stays private"
    );
    assert_eq!(std::fs::metadata(&png).unwrap().permissions().mode() & 0o7777, 0o640);

    // As root, the owner is kept too (uid and gid 65534: `nobody`).
    // SAFETY: geteuid has no preconditions.
    if unsafe { libc::geteuid() } == 0 {
        use std::os::unix::fs::MetadataExt;
        std::os::unix::fs::chown(&exr, Some(65534), Some(65534)).unwrap();
        assert!(render(&scene, &args).status.success());
        let meta = std::fs::metadata(&exr).unwrap();
        assert_eq!((meta.uid(), meta.gid(), meta.mode() & 0o7777), (65534, 65534, 0o600));
    }
}

#[test]
fn dev_stdout_into_a_pipe_is_written() {
    let (dir, scene) = scene_dir(SCENE);
    let output = prisma()
        .arg("render")
        .arg(&scene)
        .args(["--quiet", "-o", "/dev/stdout", "--preview"])
        .arg(dir.path().join("p.png"))
        .stdout(Stdio::piped())
        .output()
        .expect("prisma runs");
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(output.stdout.len() > 1000, "{} bytes", output.stdout.len());
    assert_eq!(output.stdout[..4], EXR_MAGIC, "an EXR came through the pipe");
}

#[test]
fn interrupted_render_into_a_special_file_writes_no_partial_beside_it() {
    let (dir, scene) = scene_dir(SCENE);
    let fifo = dir.path().join("out.exr");
    mkfifo(&fifo);
    let mut command = prisma();
    command
        .arg("render")
        .arg(&scene)
        .args(["--quiet", "--spp", "8", "-o"])
        .arg(&fifo)
        .env("PRISMA_TEST_STOP_AFTER_BLOCKS", "1");
    let output = run_with_limit(command, Duration::from_secs(60)).expect("the render returns");
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(130), "{message}");
    assert!(message.contains("not a regular file"), "{message}");
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["out.exr", "scene.toml"], "no out.partial.exr beside the FIFO");
}

/// A full disk, made with RLIMIT_FSIZE (SIGXFSZ ignored, so the write fails with EFBIG): the
/// export fails, and the directory it would have created is not left behind, empty.
#[test]
fn failed_export_leaves_no_empty_directory() {
    let (dir, scene) = scene_dir(MESH_SCENE);
    std::fs::write(dir.path().join("mesh_0.obj"), MESH).unwrap();
    let target = dir.path().join("new/export");
    let script = format!(
        "trap '' XFSZ; ulimit -f 1; exec '{}' export '{}' -o '{}'",
        env!("CARGO_BIN_EXE_prisma"),
        scene.display(),
        target.display()
    );
    let output = Command::new("sh").arg("-c").arg(script).output().expect("sh runs");
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    assert!(!dir.path().join("new").exists(), "the directories made for the export are removed");
    // The same export with room succeeds and creates them.
    let output = prisma().arg("export").arg(&scene).arg("-o").arg(&target).output().unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(target.join("spectra.json").is_file() && target.join("mesh_0.obj").is_file());
}
