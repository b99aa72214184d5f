//! Concave blocks: a U-shaped container (two reflex corners) holding a
//! block, and an L-shaped block standing on a base. Reflex vertices are
//! entered, never entering, so the blocks rest without spurious contacts.

use dda::scene::Scene;

fn scene(blocks: &str, loads: &str) -> dda::Model {
    let text = format!(
        r#"Scene(
    analysis: (duration: 1.0, dt: 0.002, penalty: 2e10, gravity: (0.0, -9.81)),
    // Stiff blocks: the settlement is the contacts' alone.
    materials: {{ "rock": (density: 2700.0, young: 1e12, poisson: 0.25) }},
    default_joint: Coulomb(friction_angle: 35.0),
    blocks: [
        // A U-shaped container: floor top at y = 0.5, inner walls at x = ±1.5.
        Polygon(vertices: [(-2.0, 0.0), (2.0, 0.0), (2.0, 2.0), (1.5, 2.0), (1.5, 0.5),
                           (-1.5, 0.5), (-1.5, 2.0), (-2.0, 2.0)], fixed: true),
        {blocks}
    ],
    loads: [{loads}],
)"#
    );
    let mut model = Scene::from_str(&text, "concave.ron")
        .unwrap()
        .build()
        .unwrap();
    model.driver.advance_to(0.5).unwrap();
    model
}

/// Height of the container's floor now (it sags onto its fixed points).
fn floor(model: &dda::Model) -> f64 {
    model.driver.system.blocks[0].vertices()[4].y
}

fn run_on(model: &mut dda::Model, block: usize) -> (nalgebra::Point2<f64>, nalgebra::Point2<f64>) {
    let half = model.driver.system.blocks[block].centroid();
    model.driver.advance_to(model.duration).unwrap();
    (half, model.driver.system.blocks[block].centroid())
}

#[test]
fn block_rests_on_the_floor_of_a_u_shaped_container() {
    let mut model = scene(
        "Rectangle(center: (0.0, 1.0), width: 1.0, height: 1.0),",
        "",
    );
    let (half, end) = run_on(&mut model, 1);
    // Settled by W / (p B) into the floor (the penalty per unit length
    // times the 1 m base), centred, and still.
    let settle = 2700.0 * 9.81 / (2e10 * 1.0);
    let sink = floor(&model) - model.driver.system.blocks[1].vertices()[0].y;
    assert!(
        (sink - settle).abs() < 0.05 * settle,
        "sank {sink:e} into the floor"
    );
    assert!(end.x.abs() < 1e-12);
    assert!(
        (end - half).norm() < 1e-9,
        "moved {:e} in the last 0.5 s",
        (end - half).norm()
    );
    // Only the two floor corners touch: the walls are 1 m away.
    let closed: Vec<_> = model
        .driver
        .contacts()
        .iter()
        .filter(|c| c.record.state.is_closed())
        .collect();
    assert_eq!(closed.len(), 2, "{closed:?}");
}

#[test]
fn block_in_the_inner_corner_rests_on_the_reflex_vertex() {
    // The block's lower right corner sits on the container's reflex corner.
    let mut model = scene(
        "Rectangle(center: (1.0, 1.0), width: 1.0, height: 1.0),",
        "",
    );
    let (half, end) = run_on(&mut model, 1);
    let settle = 2700.0 * 9.81 / (2e10 * 1.0);
    let sink = floor(&model) - model.driver.system.blocks[1].vertices()[1].y;
    assert!(
        (sink - settle).abs() < 0.05 * settle,
        "the corner sank {sink:e} into the floor"
    );
    assert!(
        (end - half).norm() < 1e-9,
        "moved {:e} in the last 0.5 s",
        (end - half).norm()
    );
    // The corner on the reflex vertex carries half the weight through the floor.
    let corner = model
        .driver
        .contacts()
        .iter()
        .find(|c| c.key.block_a == 1 && c.key.feature_a == 1 && c.key.feature_b == 4)
        .expect("the block's corner against the container's floor");
    assert!(
        (corner.record.normal_force / (2700.0 * 9.81 / 2.0) - 1.0).abs() < 0.01,
        "{corner:?}"
    );
}

#[test]
fn block_pushed_into_the_inner_corner_is_held_by_floor_and_wall() {
    // A horizontal load of half its weight pushes the block against the wall.
    let mut model = scene(
        "Rectangle(center: (1.0, 1.0), width: 1.0, height: 1.0),",
        "PointLoad(block: 1, point: (0.5, 1.0), force: (13243.5, 0.0)),",
    );
    let (half, end) = run_on(&mut model, 1);
    assert!(
        (end - half).norm() < 1e-9,
        "moved {:e} in the last 0.5 s",
        (end - half).norm()
    );
    // Neither the wall (x = 1.5) nor the floor (y = 0.5) is crossed by more
    // than the contact springs' compression.
    let wall = model.driver.system.blocks[0].vertices()[4].x;
    for v in model.driver.system.blocks[1].vertices() {
        assert!(
            v.x < wall + 3e-6 && v.y > floor(&model) - 3e-6,
            "vertex at {v}"
        );
    }
}

#[test]
fn l_shaped_block_stands_on_its_foot() {
    let mut model = scene(
        "Polygon(vertices: [(-1.0, 0.5), (1.0, 0.5), (1.0, 1.5), (0.0, 1.5), (0.0, 2.5), (-1.0, 2.5)]),",
        "",
    );
    let start_area = 3.0;
    let (half, end) = run_on(&mut model, 1);
    assert!(
        (end - half).norm() < 1e-9,
        "moved {:e} in the last 0.5 s",
        (end - half).norm()
    );
    let block = &model.driver.system.blocks[1];
    assert!(
        (block.area() / start_area - 1.0).abs() < 1e-5,
        "area {}",
        block.area()
    );
    assert!(block.rotation.abs() < 1e-6, "tilted by {}", block.rotation);
}
