//! `dda import`: Doolin's DDAML files, written here in the published
//! format, imported and run, give the answers of the native scenes.

mod common;

use std::path::{Path, PathBuf};

use dda::Scene;
use nalgebra::{Point2, Vector2};

/// A DDAML geometry file: joint lines (x1, y1, x2, y2, type), fixed and
/// measured points.
fn geometry(joints: &[([f64; 4], usize)], fixed: &[[f64; 2]], measured: &[[f64; 2]]) -> String {
    let mut text = String::from(
        "<?xml version=\"1.0\" standalone=\"no\"?>\n\
         <!DOCTYPE DDA SYSTEM \"geometry.dtd\">\n\
         <Berkeley:DDA xmlns:Berkeley=\"http://www.tsoft.com/~bdoolin/dda\">\n\
         <!-- Geometry section of document -->\n\
         <Berkeley:Geometry>\n   <Berkeley:Edgenodedist distance=\"0.01\"/>\n   <Jointlist>\n",
    );
    for ([x1, y1, x2, y2], kind) in joints {
        text += &format!("      <Joint type=\"{kind}\"> {x1:?} {y1:?} {x2:?} {y2:?} </Joint>\n");
    }
    text += "   </Jointlist>\n   <Fixedpointlist>\n";
    for [x, y] in fixed {
        text += &format!("      <Point> {x:?} {y:?} </Point>\n");
    }
    text += "   </Fixedpointlist>\n   <Measuredpointlist>\n";
    for [x, y] in measured {
        text += &format!("      <Point> {x:?} {y:?} </Point>\n");
    }
    text + "   </Measuredpointlist>\n</Berkeley:Geometry>\n</Berkeley:DDA>\n"
}

/// A DDAML analysis file: dynamic, plane strain, exact rotations, one
/// block material, joint properties (friction angle each).
fn analysis(steps: usize, dt: f64, density: f64, young: f64, friction: &[f64]) -> String {
    let mut text = format!(
        "<?xml version=\"1.0\" standalone=\"no\"?>\n\
         <!DOCTYPE DDA SYSTEM \"analysis.dtd\">\n\
         <Berkeley:DDA xmlns:Berkeley=\"http://www.tsoft.com/~bdoolin/dda\">\n\
         <Analysis type=\"dynamic\">\n\
         \x20 <Analysistype type=\"dynamic\"/>\n\
         \x20 <Rotation type=\"exact\"/>\n\
         \x20 <Gravity flag=\"no\"/>\n\
         \x20 <Gravaccel value=\"9.81\"/>\n\
         \x20 <Autotimestep flag=\"no\"/>\n\
         \x20 <Planestrain flag=\"yes\"/>\n\
         \x20 <Numtimesteps timesteps=\"{steps}\"/>\n\
         \x20 <Maxtimestep maxtimestep=\"{dt}\"/>\n\
         \x20 <OCLimit maxopenclose=\"6\"/>\n\
         \x20 <Maxdisplacement maxdisplacement=\"0.01\"/>\n\
         \x20 <Saveinterval step=\"10\"/>\n\
         \x20 <Blockmaterial type=\"1\">\n\
         \t<Unitmass> {density} </Unitmass>\n\
         \t<Unitweight> {} </Unitweight>\n\
         \t<Youngsmod> {young} </Youngsmod>\n\
         \t<Poissonratio> 0.25 </Poissonratio>\n\
         \t<Damping>0.0</Damping>\n\
         \t<Istress> 0.0 0.0 0.0 </Istress>\n\
         \t<Ivelocity> 0.0 0.0 0.0 </Ivelocity>\n\
         \t<Istrain> 0.0 0.0 0.0 </Istrain>\n\
         \x20 </Blockmaterial>\n",
        density * 9.81
    );
    for (k, phi) in friction.iter().enumerate() {
        text += &format!(
            "  <Jointproperties type=\"{}\">\n\t<Friction> {phi} </Friction>\n\t<Cohesion> 0.0 </Cohesion>\n\t<Tensile> 0.0 </Tensile>\n  </Jointproperties>\n",
            k + 1
        );
    }
    text + "</Analysis>\n</Berkeley:DDA>\n"
}

/// The edges of a closed outline as joint lines of one type.
fn outline(points: &[Point2<f64>], kind: usize) -> Vec<([f64; 4], usize)> {
    (0..points.len())
        .map(|i| {
            let (a, b) = (points[i], points[(i + 1) % points.len()]);
            ([a.x, a.y, b.x, b.y], kind)
        })
        .collect()
}

/// Writes the files into a fresh folder and imports them.
fn import(name: &str, geo: &str, ana: &str) -> (PathBuf, dda::import::Imported) {
    let dir = common::out_dir(name);
    std::fs::create_dir_all(&dir).unwrap();
    let (g, a) = (
        dir.join(format!("{name}.geo")),
        dir.join(format!("{name}.ana")),
    );
    std::fs::write(&g, geo).unwrap();
    std::fs::write(&a, ana).unwrap();
    let imported = dda::import::import_ddaml(&g, Some(&a)).unwrap_or_else(|e| panic!("{e}"));
    (dir, imported)
}

/// A rectangle's corners, counter-clockwise.
fn rectangle(center: Point2<f64>, width: f64, height: f64, degrees: f64) -> Vec<Point2<f64>> {
    let (s, c) = degrees.to_radians().sin_cos();
    [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .iter()
        .map(|&(x, y): &(f64, f64)| {
            let (x, y) = (x * width / 2.0, y * height / 2.0);
            center + Vector2::new(c * x - s * y, s * x + c * y)
        })
        .collect()
}

/// Runs a scene for `t` seconds; the centroid displacement of each block.
fn displacements(scene: &Scene, t: f64) -> Vec<Vector2<f64>> {
    let mut model = scene.build().unwrap_or_else(|e| panic!("{e}"));
    let start: Vec<_> = model
        .driver
        .system
        .blocks
        .iter()
        .map(|b| b.centroid())
        .collect();
    model.driver.advance_to(t).unwrap();
    model
        .driver
        .system
        .blocks
        .iter()
        .zip(start)
        .map(|(b, c)| b.centroid() - c)
        .collect()
}

/// The block on a 30° incline of `examples/sliding_block_2d.ron`, as
/// DDAML: the incline held by three fixed points, the block's joint lines
/// along the incline's top. It slides d = ½ g (sin 30° − cos 30° tan 20°) t²
/// (0.9064 m at 1 s), as the native scene does.
#[test]
fn block_on_an_incline_slides_as_the_native_scene() {
    let incline = rectangle(Point2::origin(), 20.0, 1.0, 30.0);
    let block = rectangle(Point2::new(-0.5, 0.8660254037844386), 1.0, 1.0, 30.0);
    let mut joints = outline(&incline, 1);
    joints.extend(outline(&block, 1));
    let fixed: Vec<[f64; 2]> = rectangle(Point2::origin(), 18.0, 0.5, 30.0)[..3]
        .iter()
        .map(|p| [p.x, p.y])
        .collect();
    let geo = geometry(&joints, &fixed, &[[-0.5, 0.8660254037844386]]);
    let (dir, imported) = import(
        "incline",
        &geo,
        &analysis(1000, 0.001, 2700.0, 1e10, &[20.0]),
    );
    assert_eq!(imported.scene.block_count(), 2);
    let measured = &imported.scene.measured_points;
    assert_eq!(measured.len(), 1);
    assert_eq!(measured[0].block, 1);
    assert_eq!(measured[0].point.as_slice(), [-0.5, 0.8660254037844386]);
    let (theta, phi, g) = (30f64.to_radians(), 20f64.to_radians(), 9.81);
    let exact = 0.5 * g * (theta.sin() - theta.cos() * phi.tan());
    let along = |d: &Vector2<f64>| -(d.x * theta.cos() + d.y * theta.sin());
    let imported_slide = along(&displacements(&imported.scene, 1.0)[1]);
    let native = Scene::load(common::example("sliding_block_2d.ron")).unwrap();
    let native_slide = along(&displacements(&native, 1.0)[1]);
    println!("slid {imported_slide:.6} m imported, {native_slide:.6} m native, exact {exact:.6} m");
    assert!(((imported_slide - exact) / exact).abs() < 0.01);
    assert!(((imported_slide - native_slide) / exact).abs() < 0.01);
    // The measured point's track in points.csv is the native scene's, the
    // same point written there.
    let native_text = std::fs::read_to_string(common::example("sliding_block_2d.ron"))
        .unwrap()
        .replace(
            "    blocks: [",
            "    measured_points: [(block: 1, point: (-0.5, 0.8660254037844386))],\n    blocks: [",
        );
    let native = Scene::from_str(&native_text, "native").unwrap();
    let track = |scene: &Scene, name: &str| {
        let out = dir.join(name);
        dda::run::run_scene(
            scene,
            &out,
            Default::default(),
            &dda_contact::LawRegistry::with_builtin(),
        )
        .unwrap_or_else(|e| panic!("{e:#}"));
        dda::read_points(out.join("points.csv")).unwrap()
    };
    let (imported_track, native_track) =
        (track(&imported.scene, "imported"), track(&native, "native"));
    assert_eq!(imported_track.len(), native_track.len());
    assert_eq!(imported_track.len(), 101, "every 10 steps of 0.001 s");
    for (i, n) in imported_track.iter().zip(&native_track) {
        assert!((i.time - n.time).abs() < 1e-12);
        let gap =
            (i.displacement[0] - n.displacement[0]).hypot(i.displacement[1] - n.displacement[1]);
        assert!(gap < 0.01 * exact, "t = {}: {gap} m apart", i.time);
    }
    let last = imported_track.last().unwrap();
    let slid = along(&Vector2::new(last.displacement[0], last.displacement[1]));
    assert!(
        (slid - imported_slide).abs() < 1e-9,
        "{slid} vs {imported_slide}"
    );
    // The file written by `dda import` reads back as the same scene.
    let path = dir.join("incline.ron");
    std::fs::write(&path, &imported.text).unwrap();
    assert_eq!(Scene::load(&path).unwrap().blocks, imported.scene.blocks);
    let _ = std::fs::remove_dir_all(dir);
}

/// A jointed slope on a fixed base, as DDAML: every edge of the blocks of
/// a native `JointedDomain` written as a joint line (shared edges twice),
/// type 2 along the bedding (φ = 15°), type 1 elsewhere (φ = 30°). The
/// import cuts the same blocks, and the crest wedge slides as in the
/// native scene, ½ g (sin 35° − cos 35° tan 15°) t².
#[test]
fn jointed_slope_cuts_and_slides_as_the_native_scene() {
    let native_text = r#"Scene(
    analysis: (duration: 0.5, dt: 0.001),
    materials: { "rock": (density: 2600.0, young: 1e10) },
    default_joint: Coulomb(friction_angle: 30.0),
    blocks: [
        Rectangle(center: (4.0, -0.5), width: 10.0, height: 1.0, fixed: true),
        JointedDomain(
            region: [(0.0, 0.0), (8.0, 0.0), (4.5, 6.0), (0.0, 6.0)],
            sets: [(dip: 35.0, spacing: 1.5, origin: (8.0, 0.0), law: Coulomb(friction_angle: 15.0))],
        ),
    ],
)"#;
    let native = Scene::from_str(native_text, "native.ron").unwrap();
    let bedding = Vector2::new(35f64.to_radians().cos(), -35f64.to_radians().sin());
    let mut joints = Vec::new();
    for b in native.expanded_blocks() {
        let points: Vec<Point2<f64>> = b.vertices.iter().map(|p| Point2::new(p[0], p[1])).collect();
        for (line, _) in outline(&points, 1) {
            let d = Vector2::new(line[2] - line[0], line[3] - line[1]).normalize();
            let kind = if d.perp(&bedding).abs() < 1e-9 { 2 } else { 1 };
            joints.push((line, kind));
        }
    }
    let fixed = [[-0.5, -0.5], [8.5, -0.5], [4.0, -0.9]];
    let geo = geometry(&joints, &fixed, &[[4.0, 5.5]]);
    let (dir, imported) = import(
        "slope",
        &geo,
        &analysis(500, 0.001, 2600.0, 1e10, &[30.0, 15.0]),
    );
    let (mine, theirs) = (imported.scene.expanded_blocks(), native.expanded_blocks());
    assert_eq!(mine.len(), theirs.len());
    let area = |v: &[[f64; 2]]| {
        dda_2d::polygon::signed_area(
            &v.iter()
                .map(|p| Point2::new(p[0], p[1]))
                .collect::<Vec<_>>(),
        )
    };
    let total = |bs: &[dda::SceneBlock]| bs.iter().map(|b| area(&b.vertices)).sum::<f64>();
    assert!((total(&mine) - total(&theirs)).abs() < 1e-9 * total(&theirs));
    // The crest wedge: the block holding (4, 5.5) in each.
    let holding = |bs: &[dda::SceneBlock]| {
        let p = Point2::new(4.0, 5.5);
        bs.iter()
            .position(|b| {
                dda_2d::polygon::contains(
                    &b.vertices
                        .iter()
                        .map(|q| Point2::new(q[0], q[1]))
                        .collect::<Vec<_>>(),
                    &p,
                )
            })
            .unwrap()
    };
    let (wm, wt) = (holding(&mine), holding(&theirs));
    let measured = &imported.scene.measured_points;
    assert_eq!(measured.len(), 1);
    assert_eq!(
        measured[0].block, wm,
        "the measured point is on the crest wedge"
    );
    let dip = 35f64.to_radians();
    let along = |d: &Vector2<f64>| d.x * dip.cos() - d.y * dip.sin();
    let exact = 0.5 * 9.81 * (dip.sin() - dip.cos() * 15f64.to_radians().tan()) * 0.25;
    let a = along(&displacements(&imported.scene, 0.5)[wm]);
    let b = along(&displacements(&native, 0.5)[wt]);
    println!("crest wedge slid {a:.5} m imported, {b:.5} m native, exact {exact:.5} m");
    assert!(((a - exact) / exact).abs() < 0.02);
    assert!(((a - b) / exact).abs() < 0.01);
    let _ = std::fs::remove_dir_all(dir);
}

fn import_error(geo: &str, ana: &str) -> String {
    let dir = common::out_dir("import-error");
    std::fs::create_dir_all(&dir).unwrap();
    let (g, a) = (dir.join("bad.geo"), dir.join("bad.ana"));
    std::fs::write(&g, geo).unwrap();
    std::fs::write(&a, ana).unwrap();
    let e = dda::import::import_ddaml(&g, Some(Path::new(&a)))
        .unwrap_err()
        .to_string();
    let _ = std::fs::remove_dir_all(dir);
    e
}

#[test]
fn bad_files_are_errors_naming_the_line() {
    let square = outline(&rectangle(Point2::new(0.0, 0.5), 1.0, 1.0, 0.0), 1);
    let geo = geometry(&square, &[], &[]);
    let ana = analysis(10, 0.001, 2700.0, 1e10, &[30.0]);
    // An unknown tag, on line 8 of the geometry.
    let bad = geo.replacen(
        "   <Jointlist>\n",
        "   <Jointlist>\n      <Crack> 0 0 1 1 </Crack>\n",
        1,
    );
    let e = import_error(&bad, &ana);
    assert!(
        e.contains("bad.geo:8: unknown tag <Crack> in <Jointlist>"),
        "{e}"
    );
    // A joint type without properties.
    let bad = geo.replacen("type=\"1\"", "type=\"3\"", 1);
    let e = import_error(&bad, &ana);
    assert!(
        e.contains("bad.geo:8:") && e.contains("Jointproperties"),
        "{e}"
    );
    // Three numbers for a joint.
    let bad = geo.replacen(" </Joint>", " 1.0x </Joint>", 1);
    let e = import_error(&bad, &ana);
    assert!(e.contains("bad.geo:8:") && e.contains("\"1.0x\""), "{e}");
    // A misspelt analysis item, and bolts, which are not imported.
    let e = import_error(
        &geo,
        &ana.replace("<Youngsmod>", "<Youngmod>")
            .replace("</Youngsmod>", "</Youngmod>"),
    );
    assert!(
        e.contains("bad.ana:19: unknown tag <Youngmod> in <Blockmaterial>"),
        "{e}"
    );
    let e = import_error(
        &geo.replace("</Berkeley:Geometry>", "<Boltlist/></Berkeley:Geometry>"),
        &ana,
    );
    assert!(
        e.contains("<Boltlist> (rock bolts) cannot be imported"),
        "{e}"
    );
    // Broken XML.
    let e = import_error(&geo.replace("</Jointlist>", ""), &ana);
    assert!(
        e.contains("bad.geo:") && e.contains("not well-formed XML"),
        "{e}"
    );
    // A fixed point outside every block.
    let e = import_error(&geometry(&square, &[[5.0, 5.0]], &[]), &ana);
    assert!(
        e.contains("bad.geo:") && e.contains("fixed point (5, 5) lies in no block"),
        "{e}"
    );
}

/// Hole points take out the block they lie in; load points carry the
/// analysis's force histories, in order, on the blocks they lie in.
#[test]
fn hole_and_load_points() {
    let left = rectangle(Point2::new(0.5, 0.5), 1.0, 1.0, 0.0);
    let right = rectangle(Point2::new(1.5, 0.5), 1.0, 1.0, 0.0);
    let top = rectangle(Point2::new(1.0, 1.5), 2.0, 1.0, 0.0);
    let mut joints = outline(&left, 1);
    joints.extend(outline(&right, 1));
    joints.extend(outline(&top, 1));
    let geo = geometry(&joints, &[[0.5, 0.5]], &[])
        .replace(
            "</Berkeley:Geometry>",
            "   <Loadpointlist>\n      <Point> 1.2 1.8 </Point>\n   </Loadpointlist>\n   \
             <Holepointlist>\n      <Point> 1.5 0.5 </Point>\n   </Holepointlist>\n</Berkeley:Geometry>",
        );
    let ana = analysis(10, 0.001, 2700.0, 1e10, &[30.0]).replace(
        "</Analysis>",
        "  <Loadpointlist>\n\t<Loadpoint numpoints = \"2\">\n\t0 5000 500;\n          5 5000 -500;\n\t</Loadpoint>\n  </Loadpointlist>\n</Analysis>",
    );
    let (dir, imported) = import("holes", &geo, &ana);
    let blocks = imported.scene.expanded_blocks();
    assert_eq!(blocks.len(), 2, "the right square is a hole");
    let holding = |x: f64, y: f64| {
        blocks
            .iter()
            .position(|b| {
                dda_2d::polygon::contains(
                    &b.vertices
                        .iter()
                        .map(|q| Point2::new(q[0], q[1]))
                        .collect::<Vec<_>>(),
                    &Point2::new(x, y),
                )
            })
            .unwrap()
    };
    assert_eq!(imported.scene.fixed_points[0].block, holding(0.5, 0.5));
    match &imported.scene.loads[..] {
        [dda::scene::Load::PointLoad {
            block,
            point,
            history: Some(history),
            ..
        }] => {
            assert_eq!(*block, holding(1.2, 1.8));
            assert_eq!(point.as_slice(), [1.2, 1.8]);
            let samples: Vec<&[f64]> = history.iter().map(|s| s.as_slice()).collect();
            assert_eq!(
                samples,
                [&[0.0, 5000.0, 500.0][..], &[5.0, 5000.0, -500.0][..]]
            );
        }
        other => panic!("{other:?}"),
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// `dda import GEO ANA -o SCENE` writes a scene `dda check` accepts, and
/// prints the notes on what was not carried over.
#[test]
fn the_command_writes_a_scene_that_checks() {
    let square = outline(&rectangle(Point2::new(0.0, 0.5), 1.0, 1.0, 0.0), 1);
    let base = outline(&rectangle(Point2::new(0.0, -0.5), 3.0, 1.0, 0.0), 1);
    let joints: Vec<_> = square.into_iter().chain(base).collect();
    let geo = geometry(&joints, &[[-1.0, -0.5], [1.0, -0.5]], &[[0.0, 0.5]]);
    let dir = common::out_dir("import-command");
    std::fs::create_dir_all(&dir).unwrap();
    let (g, a, out) = (dir.join("b.geo"), dir.join("b.ana"), dir.join("b.ron"));
    std::fs::write(&g, geo).unwrap();
    std::fs::write(&a, analysis(10, 0.001, 2700.0, 1e10, &[30.0])).unwrap();
    let dda = |args: &[&std::ffi::OsStr]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_dda"))
            .args(args)
            .output()
            .unwrap()
    };
    let run = dda(&[
        "import".as_ref(),
        g.as_os_str(),
        a.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(String::from_utf8_lossy(&run.stdout).contains("(2 blocks)"));
    assert!(stderr.contains("b.geo:6: <Edgenodedist>"), "{stderr}");
    let check = dda(&["check".as_ref(), out.as_os_str()]);
    assert!(
        check.status.success(),
        "{}",
        String::from_utf8_lossy(&check.stderr)
    );
    let _ = std::fs::remove_dir_all(dir);
}
