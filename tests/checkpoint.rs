//! Checkpoint and restart: a run killed after a checkpoint and resumed
//! writes the same bytes as one that never stopped, in 2D and 3D, with laws
//! that keep a history per contact; a checkpoint torn while written, of
//! another version or of another scene is handled or refused clearly.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn dda(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_dda"))
        .args(args)
        .output()
        .unwrap()
}

fn folder(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("checkpoint")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// An example with `from` replaced by `to`, written into `dir`.
fn scene(dir: &Path, example: &str, from: &str, to: &str) -> PathBuf {
    let text = std::fs::read_to_string(format!("examples/{example}")).unwrap();
    assert!(text.contains(from), "{from} is not in {example}");
    let path = dir.join(example);
    std::fs::write(&path, text.replace(from, to)).unwrap();
    path
}

fn ok(output: std::process::Output) {
    assert!(
        output.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&output.stderr)
    );
}

/// The stderr of a `dda` command that must fail with exit code 1.
fn refused(args: &[&str]) -> String {
    let result = dda(args);
    let stderr = String::from_utf8_lossy(&result.stderr).into_owned();
    assert_eq!(result.status.code(), Some(1), "{stderr}");
    stderr
}

/// The half-second sliding block in `dir`, run whole (into `dir/whole`,
/// unless `whole` is false) and with checkpoints every 0.2 s (into
/// `dir/out`): the scene's path and the two output folders.
fn sliding_block_runs(dir: &Path, whole: bool) -> (PathBuf, PathBuf, PathBuf) {
    let scene = scene(
        dir,
        "sliding_block_2d.ron",
        "duration: 1.0",
        "duration: 0.5",
    );
    let s = scene.to_str().unwrap();
    let (uninterrupted, out) = (dir.join("whole"), dir.join("out"));
    if whole {
        ok(dda(&["run", s, "--out", uninterrupted.to_str().unwrap()]));
    }
    let every = ["--checkpoint-every", "0.2"];
    ok(dda(&[
        &["run", s, "--out", out.to_str().unwrap()][..],
        &every[..],
    ]
    .concat()));
    (scene, uninterrupted, out)
}

fn read(path: impl AsRef<Path>) -> Vec<u8> {
    std::fs::read(path.as_ref()).unwrap_or_else(|e| panic!("{}: {e}", path.as_ref().display()))
}

/// Runs `scene` uninterrupted into `dir/whole`, and again into `dir/killed`
/// with checkpoints, killed with SIGKILL once its first checkpoint exists
/// (or left to finish, if it is faster than that), then resumed; both
/// folders must hold the same outputs byte for byte.
fn killed_and_resumed_matches(dir: &Path, scene: &Path, outputs: &[&str]) {
    let whole = dir.join("whole");
    let killed = dir.join("killed");
    let s = scene.to_str().unwrap();
    ok(dda(&["run", s, "--out", whole.to_str().unwrap()]));
    let mut child = Command::new(env!("CARGO_BIN_EXE_dda"))
        .args(["run", s, "--out", killed.to_str().unwrap()])
        .args(["--checkpoint-every", "0.2"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let started = Instant::now();
    while !killed.join("checkpoint.bin").exists() {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        assert!(
            started.elapsed() < Duration::from_secs(120),
            "no checkpoint"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().ok();
    child.wait().unwrap();
    // The last checkpoint is before the end, so there is always a rest to run.
    ok(dda(&["run", "--resume", killed.to_str().unwrap()]));
    for name in outputs {
        assert!(
            read(whole.join(name)) == read(killed.join(name)),
            "{name} of the resumed run differs from the uninterrupted one"
        );
    }
    let summary: serde_json::Value =
        serde_json::from_slice(&read(killed.join("summary.json"))).unwrap();
    assert_eq!(summary["status"], "finished");
}

/// 2D: the two-stage friction slide, whose contacts remember their slip
/// path (the law weakens after 5 cm of it), with measured points on both
/// blocks.
#[test]
fn a_resumed_2d_run_writes_the_same_bytes() {
    let dir = folder("2d");
    let scene = scene(
        &dir,
        "two_stage_friction_2d.ron",
        "duration: 1.0",
        "duration: 3.0",
    );
    let text = std::fs::read_to_string(&scene).unwrap().replace(
        "    blocks: [",
        "    measured_points: [(block: 1, point: (-0.3, 0.95)), (block: 0, point: (2.0, 1.0))],\n    blocks: [",
    );
    std::fs::write(&scene, text).unwrap();
    killed_and_resumed_matches(&dir, &scene, &["history.csv", "contacts.csv", "points.csv"]);
}

/// 3D: the wedge on two joints, with cohesion (its bonds are the Coulomb
/// law's history) and contacts written.
#[test]
fn a_resumed_3d_run_writes_the_same_bytes() {
    let dir = folder("3d");
    let scene = scene(
        &dir,
        "wedge_3d.ron",
        "output: (interval: 0.01)",
        "output: (interval: 0.01, contacts: true)",
    );
    killed_and_resumed_matches(&dir, &scene, &["history.csv", "contacts.csv"]);
}

/// `scene` run into `dir/first` with checkpoints every 0.3 s (the last
/// at 0.9 s), then resumed in `dir/again` from a copy of its checkpoint
/// and of the outputs `names`: the two folders and the checkpoint.
fn resumed_copy(dir: &Path, scene: &Path, names: &[&str]) -> (PathBuf, PathBuf, Vec<u8>) {
    let first = dir.join("first");
    let s = scene.to_str().unwrap();
    ok(dda(&[
        "run",
        s,
        "--out",
        first.to_str().unwrap(),
        "--checkpoint-every",
        "0.3",
    ]));
    let checkpoint = read(first.join("checkpoint.bin"));
    let again = dir.join("again");
    std::fs::create_dir_all(&again).unwrap();
    for name in names.iter().chain(&["checkpoint.bin"]) {
        std::fs::copy(first.join(name), again.join(name)).unwrap();
    }
    ok(dda(&["run", "--resume", again.to_str().unwrap()]));
    (first, again, checkpoint)
}

/// Resuming from each of several checkpoints of a finished run (the
/// outputs after it are cut off and written again) gives the same bytes,
/// VTK collections included.
#[test]
fn every_checkpoint_resumes_to_the_same_end() {
    let dir = folder("each");
    let scene = scene(
        &dir,
        "sliding_block_2d.ron",
        "output: (interval: 0.01)",
        "output: (interval: 0.01, contacts: true, vtk: true)",
    );
    let (first, again, checkpoint) = resumed_copy(&dir, &scene, &["history.csv", "contacts.csv"]);
    for name in ["history.csv", "contacts.csv", "blocks.pvd"] {
        assert!(read(first.join(name)) == read(again.join(name)), "{name}");
    }
    let last = dda::read_history(again.join("history.csv")).unwrap();
    assert_eq!(last.last().unwrap().time, 1.0);
    assert_eq!(read(first.join("checkpoint.bin")), checkpoint);
}

/// A resumed run does not settle again, and its summary still reports the
/// settling the run started with (`analysis.settle`), which the checkpoint
/// keeps; before it did, the resumed summary had none.
#[test]
fn a_resumed_run_reports_its_settling() {
    let dir = folder("settled");
    let scene = scene(
        &dir,
        "drum_column_2d.ron",
        "duration: 10.0",
        "duration: 1.0",
    );
    // Its ground motion's record, beside the scene as in examples/.
    std::fs::create_dir_all(dir.join("data")).unwrap();
    let record = "data/ground_motion_2d.csv";
    std::fs::copy(Path::new("examples").join(record), dir.join(record)).unwrap();
    let (first, again, _) = resumed_copy(&dir, &scene, &["history.csv"]);
    assert!(read(first.join("history.csv")) == read(again.join("history.csv")));
    let settling = |dir: &Path| {
        let summary: serde_json::Value =
            serde_json::from_slice(&read(dir.join("summary.json"))).unwrap();
        summary["settling"].clone()
    };
    let (before, after) = (settling(&first), settling(&again));
    assert_eq!(before["settled"], true, "{before}");
    assert_eq!(before, after);
}

/// A checkpoint torn while it was written (the run killed then) is the
/// temporary file beside it: the run resumes from the previous one. A
/// damaged checkpoint is refused with its name.
#[test]
fn a_torn_checkpoint_leaves_the_previous_one() {
    let dir = folder("torn");
    let (_, whole, out) = sliding_block_runs(&dir, true);
    let good = read(out.join("checkpoint.bin"));
    std::fs::write(out.join("checkpoint.bin.partial"), &good[..good.len() / 2]).unwrap();
    ok(dda(&["run", "--resume", out.to_str().unwrap()]));
    assert!(read(out.join("history.csv")) == read(whole.join("history.csv")));

    std::fs::write(out.join("checkpoint.bin"), &good[..good.len() / 2]).unwrap();
    let stderr = refused(&["run", "--resume", out.to_str().unwrap()]);
    assert!(stderr.contains("checkpoint.bin is damaged"), "{stderr}");
    // Another build of the same version whose saved state changed shape
    // fails the same way, and the message says so.
    assert!(stderr.contains("another build of dda"), "{stderr}");

    // One byte changed anywhere (the last of the driver's state, a
    // velocity's, once resumed from without a word) is refused too.
    for at in [good.len() - 9, good.len() / 2, good.len() - 1] {
        let mut changed = good.clone();
        changed[at] ^= 0x01;
        std::fs::write(out.join("checkpoint.bin"), &changed).unwrap();
        let stderr = refused(&["run", "--resume", out.to_str().unwrap()]);
        assert!(
            stderr.contains("checkpoint.bin is damaged")
                && stderr.contains("digest does not match"),
            "byte {at}: {stderr}"
        );
    }
}

/// A checkpoint of another version, or of a scene changed since, is
/// refused with what to do; nothing is written.
#[test]
fn a_checkpoint_of_another_version_or_scene_is_refused() {
    let dir = folder("refused");
    let (scene, _, out) = sliding_block_runs(&dir, false);
    let history = read(out.join("history.csv"));

    // Another scene: the friction angle changed after the checkpoint.
    let text = std::fs::read_to_string(&scene).unwrap();
    std::fs::write(
        &scene,
        text.replace("friction_angle: 20.0", "friction_angle: 21.0"),
    )
    .unwrap();
    let stderr = refused(&["run", "--resume", out.to_str().unwrap()]);
    assert!(stderr.contains("was taken of another scene"), "{stderr}");
    // A comment is not a change.
    std::fs::write(&scene, format!("// a note\n{text}")).unwrap();
    let mut checkpoint = dda::checkpoint::Checkpoint::read(&out).unwrap();
    assert!(checkpoint.scene(&out, None).is_ok());

    // Another version.
    checkpoint.version = "0.0.1".into();
    checkpoint.write(&out).unwrap();
    let stderr = refused(&["run", "--resume", out.to_str().unwrap()]);
    assert!(
        stderr.contains("was written by dda 0.0.1") && stderr.contains("run the scene again"),
        "{stderr}"
    );
    assert!(
        read(out.join("history.csv")) == history,
        "nothing was written"
    );

    // No checkpoint at all.
    let result = dda(&["run", "--resume", dir.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(stderr.contains("--checkpoint-every"), "{stderr}");
}

/// The explicit integrator keeps half-step velocities and the last step's
/// length: a resumed explicit run writes the same bytes too.
#[test]
fn a_resumed_explicit_run_writes_the_same_bytes() {
    let dir = folder("explicit");
    let scene = scene(
        &dir,
        "two_stage_friction_2d.ron",
        "duration: 1.0",
        "duration: 0.6, integrator: Explicit, contact_damping: 1.0",
    );
    killed_and_resumed_matches(&dir, &scene, &["history.csv", "contacts.csv"]);
}

/// The iterative solver starts each step afresh, so a resumed run with it
/// writes the same bytes too (the Heyman arch: some 35 iterations a solve).
#[test]
fn a_resumed_run_with_the_iterative_solver_writes_the_same_bytes() {
    let dir = folder("iterative");
    let scene = scene(
        &dir,
        "arch_heyman_2d.ron",
        "duration: 2.0,",
        "duration: 0.6, solver: Iterative(),",
    );
    killed_and_resumed_matches(&dir, &scene, &["history.csv"]);
}

/// A checkpoint carries the digest of the scene as parsed, so it must not
/// change when a scene is written out whole (`Scene::to_ron`, as a study
/// writes each run's scene) and read again: for every shipped example, the
/// scene read back has the digest of the one written.
#[test]
fn the_digest_of_a_scene_survives_writing_and_reading_it() {
    let dir = folder("digest");
    // Records are named relative to the scene's folder.
    std::fs::create_dir_all(dir.join("data")).unwrap();
    for entry in std::fs::read_dir("examples/data").unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, dir.join("data").join(path.file_name().unwrap())).unwrap();
    }
    let mut checked = 0;
    for entry in std::fs::read_dir("examples").unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "ron") {
            continue;
        }
        let scene = dda::Scene::load(&path).unwrap();
        let written = dir.join(path.file_name().unwrap());
        std::fs::write(&written, scene.to_ron()).unwrap();
        let again = dda::Scene::load(&written).unwrap();
        assert_eq!(
            dda::checkpoint::scene_digest(&again),
            dda::checkpoint::scene_digest(&scene),
            "{}",
            path.display()
        );
        checked += 1;
    }
    assert!(checked >= 20, "only {checked} examples");
}

/// A run's scene rewritten by `Scene::to_ron` after a checkpoint (its
/// comments and layout gone, its values the same) resumes to the bytes of
/// an uninterrupted run; the rewritten scene with one value changed is
/// refused, saying what to do, and nothing is written.
#[test]
fn a_rewritten_scene_resumes_and_a_changed_one_is_refused() {
    let dir = folder("rewritten");
    let (scene, whole, out) = sliding_block_runs(&dir, true);
    let rewritten = dda::Scene::load(&scene).unwrap().to_ron();
    assert_ne!(rewritten, std::fs::read_to_string(&scene).unwrap());
    std::fs::write(&scene, &rewritten).unwrap();
    ok(dda(&["run", "--resume", out.to_str().unwrap()]));
    assert!(read(out.join("history.csv")) == read(whole.join("history.csv")));

    let history = read(out.join("history.csv"));
    assert!(rewritten.contains("friction_angle: 20.0"), "{rewritten}");
    std::fs::write(
        &scene,
        rewritten.replace("friction_angle: 20.0", "friction_angle: 21.0"),
    )
    .unwrap();
    let stderr = refused(&["run", "--resume", out.to_str().unwrap()]);
    assert!(
        stderr.contains("was taken of another scene")
            && stderr.contains("run the scene again from the start"),
        "{stderr}"
    );
    assert!(
        read(out.join("history.csv")) == history,
        "nothing was written"
    );
}

/// `steps.csv` resumed from a checkpoint goes on as the uninterrupted
/// run's: the same steps, numbers, lengths and counts (its wall times are
/// the machine's own). A file of other columns (an earlier version's) is
/// refused, and left as it was.
#[test]
fn a_resumed_run_goes_on_with_its_steps() {
    let dir = folder("steps");
    let scene = scene(
        &dir,
        "sliding_block_2d.ron",
        "output: (interval: 0.01)",
        "output: (interval: 0.01, steps: true)",
    );
    let (first, again, _) = resumed_copy(&dir, &scene, &["history.csv", "steps.csv"]);
    let without_wall_time = |dir: &Path| {
        let mut rows = dda::step_log::read_steps(dir.join("steps.csv")).unwrap();
        for r in &mut rows {
            (r.wall_ms, r.search_ms, r.assembly_ms) = (0.0, 0.0, 0.0);
            (r.factorization_ms, r.solve_ms) = (0.0, 0.0);
            (r.open_close_ms, r.commit_ms) = (0.0, 0.0);
        }
        rows
    };
    let (whole, resumed) = (without_wall_time(&first), without_wall_time(&again));
    assert_eq!(whole.len(), 1000);
    assert!(whole == resumed, "the resumed steps.csv differs");

    let older = dir.join("older");
    std::fs::create_dir_all(&older).unwrap();
    std::fs::copy(first.join("checkpoint.bin"), older.join("checkpoint.bin")).unwrap();
    std::fs::copy(first.join("history.csv"), older.join("history.csv")).unwrap();
    let text = std::fs::read_to_string(first.join("steps.csv")).unwrap();
    let (header, body) = text.split_once('\n').unwrap();
    let fewer = header.split(",wall_ms").next().unwrap().to_string() + ",wall_ms";
    std::fs::write(older.join("steps.csv"), format!("{fewer}\n{body}")).unwrap();
    let before = read(older.join("steps.csv"));
    let stderr = refused(&["run", "--resume", older.to_str().unwrap()]);
    assert!(
        stderr.contains("its columns are not this version's")
            && stderr.contains("run the scene again from the start"),
        "{stderr}"
    );
    assert!(
        read(older.join("steps.csv")) == before,
        "nothing was written"
    );
    // A run started without it is resumed without it.
    let plain = dir.join("plain");
    let plain_scene = scene.to_str().unwrap().replace(".ron", "_plain.ron");
    std::fs::write(
        &plain_scene,
        std::fs::read_to_string(&scene)
            .unwrap()
            .replace(", steps: true", ""),
    )
    .unwrap();
    let every = "--checkpoint-every";
    ok(dda(&[
        "run",
        &plain_scene,
        "--out",
        plain.to_str().unwrap(),
        every,
        "0.3",
    ]));
    let stderr = refused(&["run", "--resume", plain.to_str().unwrap(), "--steps"]);
    assert!(
        stderr.contains("checkpointed without steps.csv"),
        "{stderr}"
    );
}
