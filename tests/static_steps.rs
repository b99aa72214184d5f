//! Static steps (`mode: Static`) near the friction limit. A static step
//! starts each block at rest, so a block past its limit slides ½·a·dt² in
//! each, a = g·(sin 30° − cos 30°·tan φ) on the 30° incline. Long against
//! the block's period, a step carries almost no inertia, and where its
//! contact slides nothing along the slope holds it but friction: the
//! Newton-Raphson iteration of a pass that locks it stalls out of balance.
//! Such a pass has not solved the step, which is cut to a third, as for
//! open-close; accepted at its best iterate instead, at a factor of safety
//! of 0.99 the block stood through its first step at every dt from 0.04 s
//! to 40 s (it moved 5.6e-6 m, its settlement into the springs), in 2D and
//! in the extruded 3D model alike.

use dda::Scene;

mod common;

/// The resting block's scene with the friction angle for a factor of
/// safety `fos`, static steps of `dt` for five steps, an output per step.
fn incline(fos: f64, dt: f64) -> Scene {
    let phi = (fos * 30f64.to_radians().tan()).atan().to_degrees();
    let text = common::example_with(
        "resting_block_2d.ron",
        "friction_angle: 35.0",
        &format!("friction_angle: {phi}"),
    )
    .replace(
        "duration: 2.0,",
        &format!("duration: {:?}, mode: Static,", 5.0 * dt),
    )
    .replace("dt: 0.001,", &format!("dt: {dt:?},"))
    .replace(
        "output: (interval: 0.01)",
        &format!("output: (interval: {dt:?})"),
    );
    Scene::from_str(&text, "static incline").unwrap()
}

/// The block's centroid in the plane of the 2D model at each output, (x,
/// y) in 2D and (x, z) in the extruded 3D model, and the run's summary.
fn centroids(name: &str, scene: &Scene) -> (Vec<[f64; 2]>, dda::Summary) {
    let out = common::run_text(name, &scene.to_ron());
    let text = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = |name: &str| header.iter().position(|h| *h == name);
    let (block, x) = (at("block").unwrap(), at("x").unwrap());
    let up = at("z").or(at("y")).unwrap();
    let centroids = lines
        .map(|l| {
            l.split(',')
                .map(|v| v.parse::<f64>().unwrap())
                .collect::<Vec<_>>()
        })
        .filter(|v| v[block] == 1.0)
        .map(|v| [v[x], v[up]])
        .collect();
    let summary =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    (centroids, summary)
}

/// The block's distance from its start at each output after the first
/// (m), and the run's summary.
fn slides(name: &str, scene: &Scene) -> (Vec<f64>, dda::Summary) {
    let (centroids, summary) = centroids(name, scene);
    let moved = (centroids[1..].iter())
        .map(|c| (c[0] - centroids[0][0]).hypot(c[1] - centroids[0][1]))
        .collect();
    (moved, summary)
}

/// The block of run `name` slid at least a quarter of `whole` (½·a·dt², m)
/// by the first output, its first step cut to thirds, and `whole` within
/// 1 % in each step from the second output on: the steps after the cut
/// grow back to dt by then.
fn slides_a_whole_step_each(name: &str, moved: &[f64], whole: f64) {
    assert!(moved[0] > 0.25 * whole, "{name}: {moved:?}");
    for step in moved[1..].windows(2) {
        let added = step[1] - step[0];
        assert!(
            (added / whole - 1.0).abs() < 0.01,
            "{name}: {added} against {whole}"
        );
    }
}

/// At a factor of safety of 0.99 the block slides from the first step, at
/// every dt, 2D and 3D: where the displacement bound does not cut the
/// steps (dt 0.04 and 0.4 s) each whole step adds ½·a·dt² within 1 %
/// (measured 0.1 %) from the second output on, and the first, cut to
/// thirds while its passes stall, at least a quarter of that (measured
/// 0.39-0.44); at dt 4 and 40 s the
/// bound holds each step to its share of the block and the block has slid
/// 0.15 and 1.5 m by the first output. At 1.01 it stands, never cut:
/// within 1e-5 m of its start (its settlement, 5.6e-6 m).
#[test]
fn a_block_past_its_friction_limit_slides_from_the_first_static_step() {
    let a = 9.81
        * (30f64.to_radians().sin() - 30f64.to_radians().cos() * 0.99 * 30f64.to_radians().tan());
    for dt in [0.04, 0.4, 4.0, 40.0] {
        let plane = incline(0.99, dt);
        let prism = dda::extrude::extrude(&plane, 1.0).unwrap();
        for (dimension, scene) in [(2, plane), (3, prism)] {
            let name = format!("static_099_{dimension}d_{dt}");
            let (moved, summary) = slides(&name, &scene);
            println!("{name}: {moved:?}, {} cuts", summary.cuts());
            let whole = 0.5 * a * dt * dt;
            assert_eq!(summary.unsolved_steps, 0, "{name}");
            if dt < 1.0 {
                slides_a_whole_step_each(&name, &moved, whole);
            } else {
                assert!(moved[0] > 0.1, "{name}: {moved:?}");
            }
        }
    }
    for dt in [0.04, 40.0] {
        let (moved, summary) = slides(&format!("static_101_{dt}"), &incline(1.01, dt));
        assert_eq!(summary.cuts(), 0);
        assert!(moved.iter().all(|&m| m < 1e-5), "{moved:?}");
    }
}

/// The same at a tenth and ten times the example's penalty (2e10 N/m³),
/// at dt 0.4 s: at 0.99 each whole step adds ½·a·dt² within 1 % and the
/// first slides; at 1.01 the block stands, never cut: it settles into its
/// springs and its own elasticity (4.7e-5 and 1.4e-6 m, against 1.5e-3
/// m slid by the first output at 0.99) and moves less than 1e-10 m from
/// the second output on (measured 1e-12).
#[test]
fn the_static_verdict_holds_at_other_penalties() {
    let a = 9.81 * 30f64.to_radians().sin() * 0.01;
    let whole = 0.5 * a * 0.4 * 0.4;
    for scale in [0.1, 10.0] {
        let at = |fos: f64| {
            let mut scene = incline(fos, 0.4);
            scene.analysis.penalty = Some(2e10 * scale);
            slides(&format!("static_{fos}_penalty_{scale}"), &scene)
        };
        let (moved, summary) = at(0.99);
        println!(
            "0.99 at {scale} × the penalty: {moved:?}, {} cuts",
            summary.cuts()
        );
        assert_eq!(summary.unsolved_steps, 0);
        slides_a_whole_step_each(&format!("0.99 at {scale}"), &moved, whole);
        let (moved, summary) = at(1.01);
        println!("1.01 at {scale} × the penalty: {moved:?}");
        assert_eq!(summary.cuts(), 0);
        assert!(moved.iter().all(|&m| m < 1e-4), "{moved:?}");
        for step in moved[1..].windows(2) {
            assert!((step[1] - step[0]).abs() < 1e-10, "{moved:?}");
        }
    }
}

/// Where the step may not be cut (`min_dt_ratio` above a third), a pass
/// that stalls out of balance is accepted at its best iterate, counted and
/// warned of, with advice that names the step and the penalty.
#[test]
fn an_unsolved_step_at_the_smallest_step_is_warned_of() {
    let mut scene = incline(0.99, 40.0);
    scene.analysis.min_dt_ratio = 0.5;
    let (moved, summary) = slides("static_099_uncut", &scene);
    println!("{moved:?}; {:?}", summary.warnings);
    assert!(summary.unsolved_steps > 0, "{summary:?}");
    assert!(
        summary
            .warnings
            .iter()
            .any(|w| w.contains("could not solve their equations") && w.contains("a smaller dt")),
        "{:?}",
        summary.warnings
    );
}

/// A 1 m block of the incline's rock resting on a 20 m ledge, its centroid
/// `overhang` beyond the ledge's edge (m; negative: over the ledge), at
/// `penalty` (N/m³), in static steps of 0.1 s for 4 s, with
/// `open_at_strength` as given.
fn ledge(overhang: f64, penalty: f64, open_at_strength: bool) -> Scene {
    let text = format!(
        r#"Scene(
    analysis: (duration: 4.0, dt: 0.1, mode: Static, penalty: {penalty:?}, gravity: (0.0, -9.81),
        open_at_strength: {open_at_strength}),
    output: (interval: 0.1),
    materials: {{ "rock": (density: 2700.0, young: 1e10, poisson: 0.25) }},
    default_joint: Coulomb(friction_angle: 35.0),
    blocks: [
        Rectangle(center: (-10.0, -0.5), width: 20.0, height: 1.0, fixed: true),
        Rectangle(center: ({overhang:?}, 0.5), width: 1.0, height: 1.0),
    ],
)"#
    );
    Scene::from_str(&text, "ledge").unwrap()
}

/// Each output's centroid less the first.
fn moved_from_start(at: &[[f64; 2]]) -> Vec<[f64; 2]> {
    (at.iter())
        .map(|c| [c[0] - at[0][0], c[1] - at[0][1]])
        .collect()
}

/// With `open_at_strength`, a block on a ledge stands in static steps while
/// its centroid is over the ledge and tips once it is beyond the edge,
/// however little: 1 mm either side of the edge (a tenth of a per cent of
/// its width), at a tenth, one and ten times the example's penalty, in 2D
/// and in the extruded 3D model. Over the ledge it settles into its
/// springs (at most 4.9e-5 m, at a tenth of the penalty) and then moves
/// less than 1e-11 m an output over its last 2 s (measured 7e-13 m);
/// beyond it, it has turned off the edge by 4 s, its centroid moved out at
/// least 1e-3 m (measured 8.3-8.6 mm) and down.
///
/// By default a closed contact opens only a contact tolerance past its
/// strength (1e-7 of w0 = 10.5 m: on a spring of about 1e10 N/m some 1e4 N,
/// 40 % of the block's weight), and the block 1 mm beyond the edge stands
/// on its back corner's pull: a static step has no inertia to carry it
/// across that band.
#[test]
fn a_block_tips_off_its_ledge_in_static_steps_as_soon_as_it_overhangs() {
    for scale in [0.1, 1.0, 10.0] {
        for overhang in [1e-3, -1e-3] {
            let plane = ledge(overhang, 2e10 * scale, true);
            let prism = dda::extrude::extrude(&plane, 1.0).unwrap();
            for (dimension, scene) in [(2, plane), (3, prism)] {
                let name = format!("ledge_{overhang}_{scale}_{dimension}d");
                let (at, _) = centroids(&name, &scene);
                let moved = moved_from_start(&at);
                let last = moved[moved.len() - 1];
                println!("{name}: moved {last:?}");
                if overhang > 0.0 {
                    assert!(last[0] > 1e-3 && last[1] < 0.0, "{name}: {last:?}");
                } else {
                    assert!(last[0].hypot(last[1]) < 1e-4, "{name}: {last:?}");
                    for pair in moved[20..].windows(2) {
                        let step = (pair[1][0] - pair[0][0]).hypot(pair[1][1] - pair[0][1]);
                        assert!(step < 1e-11, "{name}: {moved:?}");
                    }
                }
            }
        }
    }
    let (at, _) = centroids("ledge_band", &ledge(1e-3, 2e10, false));
    let moved = moved_from_start(&at);
    let last = moved[moved.len() - 1];
    println!("by default: moved {last:?}");
    assert!(last[0].hypot(last[1]) < 1e-4, "{last:?}");
}

/// With `open_at_strength`, at a factor of safety of 0.99 the block slides
/// down its incline in static steps (of 4 s, bound-limited) until the line
/// of its weight passes the incline's lower edge, at s = −10 + 0.5·tan 30°
/// = −9.7113 m along the incline from its centre, and then tips off it: in
/// 2D and in the extruded 3D model it has fallen off by 300 s. A contact
/// is committed open at the end of the step it pulls in, so the step that
/// crosses that point may end there, pulling, and the next one tips: no
/// output finds the block standing more than 0.1 m beyond it (less than a
/// step of 0.15 m; measured s = −9.690 in 2D, −9.761 m in 3D). By default
/// its back corner pulls across the band and it stands at s = −9.733 m for
/// good.
#[test]
fn a_block_sliding_off_its_incline_tips_where_its_weight_passes_the_edge() {
    let tipping = -10.0 + 0.5 * 30f64.to_radians().tan();
    let (cos, sin) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let mut plane = incline(0.99, 4.0);
    plane.analysis.duration = 300.0;
    plane.analysis.open_at_strength = true;
    let prism = dda::extrude::extrude(&plane, 1.0).unwrap();
    for (dimension, scene) in [(2, plane), (3, prism)] {
        let name = format!("static_tipping_{dimension}d");
        let (at, _) = centroids(&name, &scene);
        // Along the incline (s) and off it (n), from the incline's centre.
        let frame: Vec<[f64; 2]> = (at.iter())
            .map(|c| [c[0] * cos + c[1] * sin, -c[0] * sin + c[1] * cos])
            .collect();
        let standing: Vec<f64> = (frame.iter())
            .filter(|c| (c[1] - 1.0).abs() < 1e-3)
            .map(|c| c[0])
            .collect();
        let farthest = standing.iter().copied().fold(f64::INFINITY, f64::min);
        let last = frame[frame.len() - 1];
        println!("{name}: stood as far as s = {farthest}, ended at {last:?}");
        assert!(farthest > tipping - 0.1, "{name}: stood at s = {farthest}");
        assert!(
            last[0] < -10.5 && last[1] < 0.5,
            "{name}: ended at {last:?}"
        );
    }
}
