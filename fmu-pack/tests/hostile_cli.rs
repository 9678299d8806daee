//! `fmu-pack` under hostile conditions: outputs that cannot be written (a closed pipe, a full
//! disk), sizes past the limits, geometry that cannot give meaningful numbers, sweeps that
//! compute nothing, fits that miss their tolerance. Every case ends with a clear message and a
//! non-zero exit code, never a panic (101), an abort (134) or a hang.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const SEED_NETWORK: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../examples/networks/seed_2dof.xml"
);

/// A fast sweep: 16 panels, no extrapolation.
const QUICK: [&str; 4] = ["--panels", "16", "--levels", "1"];

/// What a run of fmu-pack gave.
struct Run {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

impl Run {
    /// No panic, no abort, no signal: the exit code fmu-pack chose.
    fn assert_clean_exit(&self, expected: i32, what: &str) {
        assert_eq!(self.code, Some(expected), "{what}: {}", self.stderr);
        assert!(!self.stderr.contains("panicked"), "{what}: {}", self.stderr);
    }
}

/// Runs fmu-pack with `args`, standard output to `stdout` and standard error to `stderr`
/// (captured when `None`), killing it after `limit`.
fn run_with(args: &[&str], stdout: Option<Stdio>, stderr: Option<Stdio>, limit: Duration) -> Run {
    let dir = scratch("captured");
    let out_path = dir.join(format!("stdout-{}", unique()));
    let err_path = dir.join(format!("stderr-{}", unique()));
    let captured = |path: &Path| Stdio::from(File::create(path).unwrap());
    let mut child = Command::new(env!("CARGO_BIN_EXE_fmu-pack"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(stdout.unwrap_or_else(|| captured(&out_path)))
        .stderr(stderr.unwrap_or_else(|| captured(&err_path)))
        .spawn()
        .expect("run fmu-pack");
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{args:?} still running after {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let read = |path: &Path| std::fs::read_to_string(path).unwrap_or_default();
    Run {
        code: status.code(),
        stdout: read(&out_path),
        stderr: read(&err_path),
    }
}

fn run(args: &[&str]) -> Run {
    run_with(args, None, None, Duration::from_secs(120))
}

fn unique() -> String {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static COUNT: AtomicUsize = AtomicUsize::new(0);
    format!(
        "{}-{}",
        std::process::id(),
        COUNT.fetch_add(1, Ordering::Relaxed)
    )
}

/// A fresh folder for one test.
fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("fmu-pack-hostile-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A pipe whose reading end is already closed: every write to it fails with EPIPE.
fn closed_pipe() -> Stdio {
    let mut fds = [0; 2];
    // SAFETY: pipe() fills two new descriptors; the read end is closed at once and the write
    // end is owned by the returned Stdio.
    unsafe {
        assert_eq!(libc::pipe(fds.as_mut_ptr()), 0);
        libc::close(fds[0]);
        Stdio::from(<std::os::fd::OwnedFd as std::os::fd::FromRawFd>::from_raw_fd(fds[1]))
    }
}

/// `/dev/full`, opened for writing: every write fails with ENOSPC, like a full disk.
fn full_device() -> Stdio {
    Stdio::from(File::options().write(true).open("/dev/full").unwrap())
}

/// `pack semicircle` of Schilder et al.'s network with the library `binary`, into `fmu`.
fn pack_seed(binary: &Path, fmu: &Path) -> Run {
    run(&[
        "pack",
        "semicircle",
        "--network",
        SEED_NETWORK,
        "--binary",
        binary.to_str().unwrap(),
        "-o",
        fmu.to_str().unwrap(),
    ])
}

/// A packed archive (from Schilder et al.'s network; the library is a stand-in file) and the stand-in.
fn packed_archive(dir: &Path) -> (PathBuf, PathBuf) {
    let binary = dir.join("libstandin.so");
    std::fs::write(&binary, b"\x7fELF stand-in").unwrap();
    let fmu = dir.join("Seed.fmu");
    pack_seed(&binary, &fmu).assert_clean_exit(0, "pack");
    (fmu, binary)
}

/// Every subcommand that prints its product, with arguments that succeed.
fn printing_commands(fmu: &Path, binary: &Path, dir: &Path) -> Vec<Vec<String>> {
    let s = |v: &[&str]| v.iter().map(|a| a.to_string()).collect::<Vec<_>>();
    let mut sweep = s(&["sweep", "semicircle", "--dofs", "heave", "--kr", "0.5:1:3"]);
    sweep.extend(s(&QUICK));
    sweep.extend(s(&["-o", "-"]));
    let mut fit = s(&["fit", "semicircle", "--dofs", "sway", "--kr", "0.05:5:20"]);
    fit.extend(s(&QUICK));
    vec![
        s(&["inspect", fmu.to_str().unwrap()]),
        s(&[
            "pack",
            "semicircle",
            "--network",
            SEED_NETWORK,
            "--binary",
            binary.to_str().unwrap(),
            "-o",
            dir.join("Again.fmu").to_str().unwrap(),
        ]),
        sweep,
        fit,
    ]
}

/// Every printing command with standard output on `device` exits 1 with `message`, no panic.
fn printing_commands_fail_on(tag: &str, device: fn() -> Stdio, message: &str) -> PathBuf {
    let dir = scratch(tag);
    let (fmu, binary) = packed_archive(&dir);
    for args in printing_commands(&fmu, &binary, &dir) {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let r = run_with(&args, Some(device()), None, Duration::from_secs(120));
        r.assert_clean_exit(1, args[0]);
        assert!(r.stderr.contains(message), "{}: {}", args[0], r.stderr);
    }
    dir
}

#[test]
fn a_closed_standard_output_is_an_error_not_a_panic() {
    let dir = printing_commands_fail_on(
        "closed-pipe",
        closed_pipe,
        "fmu-pack: error: cannot write to standard output: Broken pipe",
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[cfg(target_os = "linux")]
#[test]
fn a_full_standard_output_is_an_error_not_a_panic() {
    let dir = printing_commands_fail_on(
        "full-stdout",
        full_device,
        "fmu-pack: error: cannot write to standard output: No space left on device",
    );
    // --help is the product of its own command.
    let r = run_with(
        &["--help"],
        Some(full_device()),
        None,
        Duration::from_secs(60),
    );
    r.assert_clean_exit(1, "--help");
    assert!(
        r.stderr.contains("cannot write to standard output"),
        "{}",
        r.stderr
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[cfg(target_os = "linux")]
#[test]
fn output_files_on_a_full_disk_are_errors_naming_the_file() {
    let dir = scratch("full-files");
    let (_, binary) = packed_archive(&dir);
    // A link to /dev/full stands for a file on a full disk (and keeps the device safe: an
    // archive renamed over the link replaces the link, not the device).
    let archive = dir.join("Full.fmu");
    std::os::unix::fs::symlink("/dev/full", &archive).unwrap();
    let archive = archive.to_str().unwrap();
    let pack = [
        "pack",
        "semicircle",
        "--network",
        SEED_NETWORK,
        "--binary",
        binary.to_str().unwrap(),
        "-o",
        archive,
    ];
    let quick_sweep = |extra: &[&'static str]| {
        let mut v = vec!["sweep", "semicircle", "--dofs", "heave", "--kr", "0.5:1:3"];
        v.extend(QUICK);
        v.extend(extra);
        v
    };
    let mut fit = vec!["fit", "semicircle", "--dofs", "sway", "--kr", "0.05:5:20"];
    fit.extend(QUICK);
    fit.extend(["--network-out", "/dev/full"]);
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (pack.to_vec(), archive),
        (quick_sweep(&["-o", "/dev/full"]), "/dev/full"),
        (
            quick_sweep(&["-o", "/dev/null", "--excitation", "/dev/full"]),
            "/dev/full",
        ),
        (fit, "/dev/full"),
    ];
    for (args, path) in cases {
        let r = run(&args);
        r.assert_clean_exit(1, args[0]);
        let line = r.stderr.lines().last().unwrap_or_default();
        assert!(
            line.starts_with("fmu-pack: error: ")
                && line.contains(path)
                && line.contains("No space left on device"),
            "{args:?}: {}",
            r.stderr
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[cfg(target_os = "linux")]
#[test]
fn a_full_standard_error_does_not_crash_the_work() {
    let dir = scratch("full-stderr");
    let table = dir.join("table.csv");
    let mut args = vec!["sweep", "semicircle", "--dofs", "heave", "--kr", "0.5:1:3"];
    args.extend(QUICK);
    args.extend(["-o", table.to_str().unwrap()]);
    let r = run_with(&args, None, Some(full_device()), Duration::from_secs(120));
    // Diagnostics that cannot be written are dropped; the table is the product.
    assert_eq!(r.code, Some(0), "{}", r.stdout);
    let text = std::fs::read_to_string(&table).unwrap();
    assert_eq!(text.lines().filter(|l| l.starts_with("5e-1,")).count(), 1);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn sizes_past_the_limits_are_refused_naming_the_option_and_the_limit() {
    let cases: [(&[&str], &str); 8] = [
        (
            &["--kr", "0.1:5:100000000000"],
            "at most 100000 frequencies",
        ),
        (
            &["--kr", "0.1:5:18446744073709551615"],
            "at most 100000 frequencies",
        ),
        (
            &["--panels", "100000000"],
            "--panels 100000000: at most 8192",
        ),
        (
            &["--panels", "18446744073709551615"],
            "--panels 18446744073709551615: at most 8192",
        ),
        (&["--levels", "13"], "--levels 13: at most 12"),
        (
            &["--threads", "100000000"],
            "--threads 100000000: at most 1024",
        ),
        (&["--threads", "0"], "--threads 0: at least 1"),
        (&["--levels", "0"], "--levels 0: at least 1"),
    ];
    for (extra, expected) in cases {
        let mut args = vec!["sweep", "semicircle", "-o", "/dev/null"];
        args.extend(extra);
        let r = run_with(&args, None, None, Duration::from_secs(60));
        r.assert_clean_exit(1, &extra.join(" "));
        assert!(r.stderr.contains(expected), "{extra:?}: {}", r.stderr);
        // Refused before any work: no sweep started.
        assert!(!r.stderr.contains("time summed"), "{extra:?}: {}", r.stderr);
    }
    // Malformed numbers are the parser's.
    let r = run(&["sweep", "semicircle", "--panels", "1e8", "-o", "/dev/null"]);
    r.assert_clean_exit(2, "--panels 1e8");
    assert!(r.stderr.contains("--panels"), "{}", r.stderr);
    let r = run(&[
        "sweep",
        "semicircle",
        "--kr",
        "0.1:5:1e11",
        "-o",
        "/dev/null",
    ]);
    r.assert_clean_exit(1, "--kr 0.1:5:1e11");
    assert!(r.stderr.contains("COUNT '1e11'"), "{}", r.stderr);
}

/// The attack file: a box section with `half_beam`, one mode entry and a scale for every
/// coordinate substituted.
fn box_hull(dir: &Path, name: &str, half_beam: &str, mode_entry: &str, scale: f64) -> PathBuf {
    let p = |x: f64| format!("{:e}", x * scale);
    let text = format!(
        "<hull name=\"box\" half_beam=\"{half_beam}\" units=\"m\">\n\
         <contour closed=\"false\">\n\
         <point x=\"{}\" y=\"0\"/>\n<point x=\"{}\" y=\"{}\"/>\n\
         <point x=\"{}\" y=\"{}\"/>\n<point x=\"{}\" y=\"0\"/>\n\
         </contour>\n\
         <rigid name=\"sway\" kind=\"sway\"/>\n\
         <rigid name=\"heave\" kind=\"heave\"/>\n\
         <mode name=\"m\"><u x=\"0\" y=\"0\"/><u x=\"0\" y=\"{mode_entry}\"/>\
         <u x=\"0\" y=\"1\"/><u x=\"0\" y=\"0\"/></mode>\n\
         </hull>\n",
        p(-2.0),
        p(-2.0),
        p(-1.0),
        p(2.0),
        p(-1.0),
        p(2.0)
    );
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn geometry_that_cannot_give_meaningful_numbers_is_refused_with_file_and_line() {
    let dir = scratch("geometry");
    let cases = [
        (
            box_hull(&dir, "wide.xml", "1e154", "1", 1.0),
            ":1: half_beam = 1e154 m",
        ),
        (
            box_hull(&dir, "mode.xml", "2", "1e154", 1.0),
            ":10: displacement (0, 1e154)",
        ),
        (
            box_hull(&dir, "tiny.xml", "2e-160", "1", 1e-160),
            ":1: half_beam = 2e-160 m",
        ),
        (
            box_hull(&dir, "small.xml", "2", "1", 1e-160),
            ":2: the section's size",
        ),
    ];
    for (path, expected) in cases {
        let file = path.to_str().unwrap();
        let mut args = vec!["sweep", file, "--kr", "0.5:1:3", "-o", "/dev/null"];
        args.extend(QUICK);
        let r = run(&args);
        r.assert_clean_exit(1, file);
        assert!(
            r.stderr.contains(&format!("{file}{expected}")),
            "{file}: {}",
            r.stderr
        );
    }
    // A contour of 100,000 points: refused at once (its pairwise checks took minutes).
    let many = dir.join("many.xml");
    let mut text = String::from("<hull name=\"many\" half_beam=\"1\">\n<contour>\n");
    let n = 100_000;
    for i in 0..n {
        let t = std::f64::consts::PI * i as f64 / (n - 1) as f64;
        let (x, y) = match i {
            0 => (-1.0, 0.0),
            _ if i == n - 1 => (1.0, 0.0),
            _ => (-t.cos(), -t.sin()),
        };
        text.push_str(&format!("<point x=\"{x:e}\" y=\"{y:e}\"/>\n"));
    }
    text.push_str("</contour>\n<rigid name=\"heave\" kind=\"heave\"/>\n</hull>\n");
    std::fs::write(&many, text).unwrap();
    let file = many.to_str().unwrap();
    let r = run(&["sweep", file, "--kr", "0.5:1:3", "-o", "/dev/null"]);
    r.assert_clean_exit(1, file);
    assert!(
        r.stderr.contains(&format!(
            "{file}:2: the contour has 100000 points; at most 8192"
        )),
        "{}",
        r.stderr
    );
    // Within the bounds the same section sweeps, and every number in the table is finite.
    let fine = box_hull(&dir, "fine.xml", "2", "0.5", 1.0);
    let mut args = vec![
        "sweep",
        fine.to_str().unwrap(),
        "--kr",
        "0.5:1:3",
        "-o",
        "-",
    ];
    args.extend(QUICK);
    let r = run(&args);
    r.assert_clean_exit(0, "fine.xml");
    let values: Vec<f64> = r
        .stdout
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("kR"))
        .flat_map(|l| l.split(',').skip(3).map(|v| v.parse::<f64>().unwrap()))
        .collect();
    assert_eq!(values.len(), 2 * (3 * 9 + 9 + 5), "{}", r.stdout);
    assert!(values.iter().all(|v| v.is_finite()));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_sweep_that_computed_nothing_is_an_error() {
    let dir = scratch("nothing");
    let (_, binary) = packed_archive(&dir);
    let archive = dir.join("Nothing.fmu");
    // From kR = 1e6 up the panel method's values overflow: every frequency fails.
    let hull = ["semicircle", "--dofs", "heave", "--kr", "1e6:1e7:3"];
    let band = ["--band", "1e5:2e7"];
    let commands: [Vec<&str>; 3] = [
        [&["sweep"][..], &hull, &QUICK, &["-o", "-"]].concat(),
        [&["fit"][..], &hull, &QUICK, &band].concat(),
        [
            &["pack"][..],
            &hull,
            &QUICK,
            &band,
            &["--binary", binary.to_str().unwrap()],
            &["-o", archive.to_str().unwrap()],
        ]
        .concat(),
    ];
    for args in commands {
        let r = run(&args);
        r.assert_clean_exit(1, args[0]);
        assert!(
            r.stderr
                .contains("error: all 3 frequencies of the sweep failed; kR = 1000000: "),
            "{}: {}",
            args[0],
            r.stderr
        );
        assert!(r.stdout.is_empty(), "{}: {}", args[0], r.stdout);
    }
    assert!(!archive.exists());
    // One frequency: the message says so.
    let args = [
        &["sweep", "semicircle", "--kr", "1e6:1e6:1"][..],
        &QUICK,
        &["-o", "-"],
    ]
    .concat();
    let r = run(&args);
    r.assert_clean_exit(1, "one frequency");
    assert!(
        r.stderr
            .contains("the sweep's only frequency failed; kR = 1000000: "),
        "{}",
        r.stderr
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn numbers_in_messages_are_readable() {
    let mut args = vec![
        "sweep",
        "semicircle",
        "--dofs",
        "heave",
        "--kr",
        "0.5:1e300:2",
    ];
    args.extend(QUICK);
    args.extend(["-o", "-"]);
    let r = run(&args);
    r.assert_clean_exit(0, "one good frequency");
    assert!(
        r.stderr
            .contains("warning: kR = 1e300 failed and is left out"),
        "{}",
        r.stderr
    );
    assert!(r.stdout.contains("# failed: kR = 1e300: "), "{}", r.stdout);
    assert!(!r.stderr.contains("0000000000"), "{}", r.stderr);
    assert!(!r.stdout.contains("0000000000"), "{}", r.stdout);
}

#[test]
fn pack_refuses_a_fit_that_misses_the_tolerance_unless_allowed() {
    let dir = scratch("tolerance");
    let (_, binary) = packed_archive(&dir);
    let archive = dir.join("Loose.fmu");
    let mut args = vec![
        "pack",
        "semicircle",
        "--dofs",
        "sway",
        "--kr",
        "0.05:5:20",
        "--order",
        "1",
        "--tol",
        "0.0001",
        "--binary",
        binary.to_str().unwrap(),
        "-o",
        archive.to_str().unwrap(),
    ];
    args.extend(QUICK);
    let r = run(&args);
    r.assert_clean_exit(1, "tolerance missed");
    assert!(
        r.stderr.contains("the fit misses the tolerance")
            && r.stderr.contains("--allow-tolerance-miss"),
        "{}",
        r.stderr
    );
    assert!(!archive.exists());
    args.push("--allow-tolerance-miss");
    let r = run(&args);
    r.assert_clean_exit(0, "tolerance miss allowed");
    assert!(r.stdout.contains("NOT met"), "{}", r.stdout);
    assert!(archive.is_file());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn inspect_errors_name_the_archive() {
    let dir = scratch("inspect");
    let not_zip = dir.join("notes.fmu");
    std::fs::write(&not_zip, "not an archive").unwrap();
    let empty = dir.join("empty.fmu");
    {
        let mut zip = zip::ZipWriter::new(File::create(&empty).unwrap());
        zip.start_file("readme.txt", zip::write::SimpleFileOptions::default())
            .unwrap();
        std::io::Write::write_all(&mut zip, b"nothing").unwrap();
        zip.finish().unwrap();
    }
    for (path, words) in [
        (dir.join("missing.fmu"), "cannot open"),
        (not_zip, "not a zip archive"),
        (empty, "no modelDescription.xml"),
    ] {
        let file = path.to_str().unwrap();
        let r = run(&["inspect", file]);
        r.assert_clean_exit(1, file);
        assert!(
            r.stderr.starts_with(&format!("fmu-pack: error: {file}: ")) && r.stderr.contains(words),
            "{file}: {}",
            r.stderr
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_pack_that_cannot_write_its_osp_description_leaves_the_archive_as_it_was() {
    let dir = scratch("osp-folder");
    let (fmu, binary) = packed_archive(&dir);
    let description = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.to_string_lossy().ends_with("_OspModelDescription.xml"))
        .expect("pack wrote an OSP description beside its archive");
    // The description's name taken by a folder: the second write must fail.
    std::fs::remove_file(&description).unwrap();
    std::fs::create_dir(&description).unwrap();
    // Bytes no pack writes, to tell whether the archive was replaced.
    std::fs::write(&fmu, b"the earlier archive").unwrap();
    let r = pack_seed(&binary, &fmu);
    r.assert_clean_exit(1, "pack");
    assert!(
        r.stderr.contains("it is a folder") && r.stderr.contains("_OspModelDescription.xml"),
        "{}",
        r.stderr
    );
    assert_eq!(
        std::fs::read(&fmu).unwrap(),
        b"the earlier archive",
        "the archive was replaced"
    );
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".part"))
        .collect();
    assert!(left.is_empty(), "temporary files left: {left:?}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn leaving_out_the_windows_dll_and_giving_one_are_refused_together() {
    let dir = scratch("no-windows");
    let out = dir.join("x.fmu");
    let run = run(&[
        "pack",
        "semicircle",
        "--no-windows",
        "--binary-windows",
        "hydrofmu.dll",
        "-o",
        out.to_str().unwrap(),
    ]);
    run.assert_clean_exit(2, "--no-windows with --binary-windows");
    assert!(run.stderr.contains("--no-windows"), "{}", run.stderr);
    assert!(!out.exists());
}
