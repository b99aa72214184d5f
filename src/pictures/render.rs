//! `dda render DIR`: an animated GIF of a run and a still (SVG and PNG),
//! blocks coloured by a chosen field, contacts as force lines.
//!
//! The blocks are the run's scene rebuilt (its path is in `summary.json`,
//! or given with `--scene`) and moved rigidly to each output time by the
//! centroid and rotation in `history.csv`: a deformable block's strain is
//! not drawn. 3D runs are drawn in a fixed oblique view from the
//! south-east, 25° above the horizon (x east, y north, z up), faces shaded
//! by the light and drawn far to near. Contacts come from `contacts.csv`
//! when the run wrote it: each closed contact is a line through its point
//! along its normal, as long as its normal force is large against the
//! run's typical one (its 90th percentile), black while locked and red
//! while sliding.

use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Context};
use dda_3d::Polyhedron;
use dda_contact::LawRegistry;
use dda_core::ContactState;
use nalgebra::{Point2, Point3, Rotation2, Rotation3, Vector2, Vector3};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::{create_dir, norm, palette, register_font, viridis, RunData, FAMILY};
use crate::features::{contact_2d, contact_normal_3d, contact_point_3d};
use crate::scene::{AnyModel, Scene};

/// Frames drawn when no count is asked for: every output time up to this
/// many, else this many evenly spaced.
pub const DEFAULT_MAX_FRAMES: usize = 200;

/// What colours the blocks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum ColorField {
    /// Distance of the centroid from its start, m.
    #[default]
    Displacement,
    /// Speed of the centroid, m/s.
    Velocity,
    /// Von Mises equivalent stress, Pa.
    Stress,
    /// One colour per block.
    Block,
}

impl ColorField {
    fn label(self) -> &'static str {
        match self {
            Self::Displacement => "displacement (m)",
            Self::Velocity => "speed (m/s)",
            Self::Stress => "von Mises stress (Pa)",
            Self::Block => "block",
        }
    }
}

/// What `dda render` is asked for.
#[derive(Debug, Clone)]
pub struct RenderOptions {
    pub color: ColorField,
    /// Frames of the animation; `None`: see [`DEFAULT_MAX_FRAMES`].
    pub frames: Option<usize>,
    /// The scene file; `None`: the one `summary.json` names.
    pub scene: Option<PathBuf>,
    /// Where the pictures go; `None`: `DIR/render`.
    pub out: Option<PathBuf>,
    /// Time of the still, s; `None`: the last output time drawn.
    pub still: Option<f64>,
    /// Draw output times up to this one only, s; `None`: to the end.
    pub until: Option<f64>,
    /// Image width and height in pixels.
    pub size: (u32, u32),
    /// A progress bar on stderr.
    pub progress: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            color: ColorField::default(),
            frames: None,
            scene: None,
            out: None,
            still: None,
            until: None,
            size: (800, 600),
            progress: false,
        }
    }
}

/// What was written and how many frames the animation has.
#[derive(Debug, Clone)]
pub struct Rendered {
    pub files: Vec<PathBuf>,
    pub frames: usize,
}

/// The blocks as the scene builds them, at time 0.
enum Shapes {
    Plane(Vec<Vec<Point2<f64>>>),
    Space(Vec<Polyhedron>),
}

/// Blocks at one output time, in the scene's coordinates.
enum Posed {
    Plane(Vec<Vec<Point2<f64>>>),
    Space(Vec<Polyhedron>),
}

/// A filled outline on the screen, drawn in order.
struct Patch {
    depth: f64,
    /// A 3D face's outward normal and a point of its plane, for ordering.
    plane: Option<(Vector3<f64>, Vector3<f64>)>,
    /// The face's corners in the scene (3D).
    corners: Vec<Vector3<f64>>,
    points: Vec<(f64, f64)>,
    colour: RGBColor,
}

/// A force line on the screen.
struct ForceLine {
    from: (f64, f64),
    to: (f64, f64),
    sliding: bool,
}

/// Renders the run in `dir`; `registry` builds the scene's `Custom` laws.
pub fn render(
    dir: &Path,
    options: &RenderOptions,
    registry: &LawRegistry,
) -> anyhow::Result<Rendered> {
    let mut run = RunData::load(dir)?;
    if let Some(until) = options.until {
        let kept = run.times.iter().take_while(|&&t| t <= until).count();
        if kept == 0 {
            bail!(
                "--until {until}: the run's first output time is {} s",
                run.times[0]
            );
        }
        run.times.truncate(kept);
        run.blocks.truncate(kept);
        if let Some(c) = &mut run.contacts {
            c.truncate(kept);
        }
    }
    let shapes = initial_shapes(&run, options.scene.as_deref(), registry)?;
    let frames = choose_frames(run.times.len(), options.frames)?;
    let still = match options.still {
        None => run.times.len() - 1,
        Some(t) => nearest(&run.times, t),
    };
    let out = options.out.clone().unwrap_or_else(|| dir.join("render"));
    create_dir(&out)?;
    register_font();

    let mut fitted = frames.clone();
    fitted.push(still);
    let view = View::new(&run, &shapes, &fitted, options.size);
    let scale = field_scale(&run, options.color);
    let force_scale = typical_force(&run);
    let draw_frame = |k: usize| -> (Vec<Patch>, Vec<ForceLine>) {
        let posed = pose(&shapes, &run, k);
        let patches = view.patches(&posed, &run, k, options.color, scale);
        let lines = view.force_lines(&posed, &run, k, force_scale);
        (patches, lines)
    };

    let bar = crate::progress::progress_bar(options.progress);
    bar.set_length(frames.len() as u64);
    let gif_path = out.join("animation.gif");
    let (w, h) = options.size;
    let file = std::fs::File::create(&gif_path)
        .with_context(|| format!("cannot create {}", gif_path.display()))?;
    let mut encoder = gif::Encoder::new(file, w as u16, h as u16, &[])
        .with_context(|| format!("cannot write {}", gif_path.display()))?;
    encoder.set_repeat(gif::Repeat::Infinite)?;
    let mut buffer = vec![0u8; (w * h * 3) as usize];
    for &k in &frames {
        let (patches, lines) = draw_frame(k);
        {
            let root = BitMapBackend::with_buffer(&mut buffer, options.size).into_drawing_area();
            draw(&root, &patches, &lines, &run, k, options.color, scale)?;
        }
        let mut frame = gif::Frame::from_rgb_speed(w as u16, h as u16, &buffer, 20);
        // Hundredths of a second: about 12 frames a second.
        frame.delay = 8;
        encoder
            .write_frame(&frame)
            .with_context(|| format!("cannot write {}", gif_path.display()))?;
        bar.inc(1);
    }
    drop(encoder);
    bar.finish_and_clear();

    let (patches, lines) = draw_frame(still);
    let svg = out.join("still.svg");
    let png = out.join("still.png");
    draw(
        &SVGBackend::new(&svg, options.size).into_drawing_area(),
        &patches,
        &lines,
        &run,
        still,
        options.color,
        scale,
    )?;
    draw(
        &BitMapBackend::new(&png, options.size).into_drawing_area(),
        &patches,
        &lines,
        &run,
        still,
        options.color,
        scale,
    )?;
    Ok(Rendered {
        files: vec![gif_path, svg, png],
        frames: frames.len(),
    })
}

/// The scene's blocks at time 0, from `scene` or the path in summary.json.
fn initial_shapes(
    run: &RunData,
    scene: Option<&Path>,
    registry: &LawRegistry,
) -> anyhow::Result<Shapes> {
    let path = match (scene, &run.summary) {
        (Some(p), _) => p.to_path_buf(),
        (None, Some(s)) => PathBuf::from(&s.scene),
        (None, None) => bail!(
            "{} not found, so the run's scene is unknown: give it with --scene SCENE.ron",
            run.dir.join("summary.json").display()
        ),
    };
    if !path.is_file() {
        bail!(
            "the run's scene {} (named in {}) is not found from here: give it with --scene SCENE.ron",
            path.display(),
            run.dir.join("summary.json").display()
        );
    }
    let scene = Scene::load(&path)?;
    let shapes = match scene.build_any_with(registry)? {
        AnyModel::Plane(m) => Shapes::Plane(
            m.driver
                .system
                .blocks
                .iter()
                .map(|b| b.vertices().to_vec())
                .collect(),
        ),
        AnyModel::Space(m) => Shapes::Space(
            m.driver
                .system
                .blocks
                .iter()
                .map(|b| b.shape().clone())
                .collect(),
        ),
    };
    let (count, dimension) = match &shapes {
        Shapes::Plane(b) => (b.len(), 2),
        Shapes::Space(b) => (b.len(), 3),
    };
    if count != run.block_count() || dimension != run.dimension {
        bail!(
            "{} has {count} blocks in {dimension}D but the run in {} has {} in {}D: give the run's own scene with --scene",
            path.display(),
            run.dir.display(),
            run.block_count(),
            run.dimension
        );
    }
    Ok(shapes)
}

/// Output-time indices of the animation.
fn choose_frames(times: usize, asked: Option<usize>) -> anyhow::Result<Vec<usize>> {
    let n = match asked {
        Some(0) => bail!("--frames must be at least 1"),
        Some(n) if n > times => bail!(
            "--frames {n}: the run has only {times} output times (give at most {times}, or a smaller output.interval when running)"
        ),
        Some(n) => n,
        None => times.min(DEFAULT_MAX_FRAMES),
    };
    if n == 1 {
        return Ok(vec![times - 1]);
    }
    Ok((0..n)
        .map(|j| ((j * (times - 1)) as f64 / (n - 1) as f64).round() as usize)
        .collect())
}

fn nearest(times: &[f64], t: f64) -> usize {
    (0..times.len())
        .min_by(|&a, &b| (times[a] - t).abs().total_cmp(&(times[b] - t).abs()))
        .unwrap_or(0)
}

/// The blocks moved rigidly from time 0 to output time k.
fn pose(shapes: &Shapes, run: &RunData, k: usize) -> Posed {
    let (start, now) = (&run.blocks[0], &run.blocks[k]);
    match shapes {
        Shapes::Plane(blocks) => Posed::Plane(
            blocks
                .iter()
                .enumerate()
                .map(|(i, corners)| {
                    let turn = Rotation2::new(now[i].rotation[2] - start[i].rotation[2]);
                    let (c0, c) = (start[i].position, now[i].position);
                    let (c0, c) = (Vector2::new(c0[0], c0[1]), Vector2::new(c[0], c[1]));
                    corners
                        .iter()
                        .map(|p| Point2::from(c + turn * (p.coords - c0)))
                        .collect()
                })
                .collect(),
        ),
        Shapes::Space(blocks) => Posed::Space(
            blocks
                .iter()
                .enumerate()
                .map(|(i, shape)| {
                    let r = |v: [f64; 3]| Rotation3::from_scaled_axis(Vector3::from(v));
                    let turn = r(now[i].rotation) * r(start[i].rotation).inverse();
                    let (c0, c) = (
                        Vector3::from(start[i].position),
                        Vector3::from(now[i].position),
                    );
                    shape.moved(|p| Point3::from(c + turn * (p.coords - c0)))
                })
                .collect(),
        ),
    }
}

/// The normal force drawn at full length: the 90th percentile of the run's
/// closed contacts', so a few impact spikes do not shrink every other line.
fn typical_force(run: &RunData) -> f64 {
    let mut forces: Vec<f64> = run
        .contacts
        .iter()
        .flatten()
        .flatten()
        .map(|c| c.normal_force)
        .filter(|f| *f > 0.0 && f.is_finite())
        .collect();
    if forces.is_empty() {
        return 0.0;
    }
    forces.sort_by(f64::total_cmp);
    forces[(0.9 * (forces.len() - 1) as f64).round() as usize]
}

/// The largest value of the colour field over the run (1 if none).
fn field_scale(run: &RunData, field: ColorField) -> f64 {
    let mut largest = 0.0f64;
    for k in 0..run.times.len() {
        for i in 0..run.block_count() {
            largest = largest.max(field_value(run, k, i, field));
        }
    }
    if largest > 0.0 {
        largest
    } else {
        1.0
    }
}

fn field_value(run: &RunData, k: usize, i: usize, field: ColorField) -> f64 {
    let b = &run.blocks[k][i];
    match field {
        ColorField::Displacement => run.displacement(k, i),
        ColorField::Velocity => norm(b.velocity),
        ColorField::Stress => b.stress,
        ColorField::Block => i as f64,
    }
}

fn block_colour(run: &RunData, k: usize, i: usize, field: ColorField, scale: f64) -> RGBColor {
    let (r, g, b) = match field {
        ColorField::Block => palette(i),
        _ => viridis(field_value(run, k, i, field) / scale),
    };
    RGBColor(r, g, b)
}

/// The picture's frame: where the scene lands on the screen.
struct View {
    dimension: u32,
    /// Towards the viewer (3D), screen right and up.
    toward: Vector3<f64>,
    right: Vector3<f64>,
    up: Vector3<f64>,
    /// Screen = origin + scale · (u − u0, v0 − v).
    u0: f64,
    v0: f64,
    scale: f64,
    origin: (f64, f64),
    /// The picture's height, pixels.
    height: f64,
}

/// Pixels kept for the title (top) and colour bar (right).
const TOP: f64 = 40.0;
const RIGHT: f64 = 110.0;
const MARGIN: f64 = 20.0;

impl View {
    fn new(run: &RunData, shapes: &Shapes, frames: &[usize], (w, h): (u32, u32)) -> Self {
        let (az, el) = (-60f64.to_radians(), 25f64.to_radians());
        let toward = Vector3::new(el.cos() * az.cos(), el.cos() * az.sin(), el.sin());
        let right = Vector3::new(-az.sin(), az.cos(), 0.0);
        let up = toward.cross(&right);
        let mut view = Self {
            dimension: run.dimension,
            toward,
            right,
            up,
            u0: 0.0,
            v0: 0.0,
            scale: 1.0,
            origin: (MARGIN, TOP),
            height: h as f64,
        };
        // Fit every drawn frame, so the camera stays still.
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for &k in frames {
            view.each_point(&pose(shapes, run, k), |u, v| {
                lo = [lo[0].min(u), lo[1].min(v)];
                hi = [hi[0].max(u), hi[1].max(v)];
            });
        }
        let (room_w, room_h) = (w as f64 - MARGIN - RIGHT, h as f64 - TOP - MARGIN);
        let (span_u, span_v) = ((hi[0] - lo[0]).max(1e-12), (hi[1] - lo[1]).max(1e-12));
        view.scale = (room_w / span_u).min(room_h / span_v);
        // Centred in the room left.
        view.origin = (
            MARGIN + (room_w - view.scale * span_u) / 2.0,
            TOP + (room_h - view.scale * span_v) / 2.0,
        );
        view.u0 = lo[0];
        view.v0 = hi[1];
        view
    }

    /// Screen-plane coordinates (u right, v up) of a point of the scene.
    fn plane(&self, p: [f64; 3]) -> (f64, f64) {
        if self.dimension == 2 {
            (p[0], p[1])
        } else {
            let p = Vector3::from(p);
            (p.dot(&self.right), p.dot(&self.up))
        }
    }

    fn screen(&self, p: [f64; 3]) -> (f64, f64) {
        let (u, v) = self.plane(p);
        (
            self.origin.0 + self.scale * (u - self.u0),
            self.origin.1 + self.scale * (self.v0 - v),
        )
    }

    fn each_point(&self, posed: &Posed, mut f: impl FnMut(f64, f64)) {
        match posed {
            Posed::Plane(blocks) => blocks.iter().flatten().for_each(|p| {
                let (u, v) = self.plane([p.x, p.y, 0.0]);
                f(u, v)
            }),
            Posed::Space(blocks) => blocks.iter().flat_map(|b| b.vertices()).for_each(|p| {
                let (u, v) = self.plane([p.x, p.y, p.z]);
                f(u, v)
            }),
        }
    }

    fn patches(
        &self,
        posed: &Posed,
        run: &RunData,
        k: usize,
        field: ColorField,
        scale: f64,
    ) -> Vec<Patch> {
        let mut patches = Vec::new();
        match posed {
            Posed::Plane(blocks) => {
                for (i, corners) in blocks.iter().enumerate() {
                    patches.push(Patch {
                        depth: i as f64,
                        plane: None,
                        corners: Vec::new(),
                        points: corners
                            .iter()
                            .map(|p| self.screen([p.x, p.y, 0.0]))
                            .collect(),
                        colour: block_colour(run, k, i, field, scale),
                    });
                }
            }
            Posed::Space(blocks) => {
                let light = Vector3::new(0.3, -0.4, 0.87).normalize();
                for (i, block) in blocks.iter().enumerate() {
                    let RGBColor(r, g, b) = block_colour(run, k, i, field, scale);
                    for (f, face) in block.faces().iter().enumerate() {
                        let n = block.normal(f);
                        if n.dot(&self.toward) <= 0.0 {
                            continue;
                        }
                        let shade = 0.55 + 0.45 * n.dot(&light).max(0.0);
                        let s = |c: u8| (c as f64 * shade).round() as u8;
                        let corners: Vec<Vector3<f64>> =
                            face.iter().map(|&v| block.vertices()[v].coords).collect();
                        patches.push(Patch {
                            depth: block.face_centroid(f).coords.dot(&self.toward),
                            plane: Some((n, corners[0])),

                            corners,
                            points: face
                                .iter()
                                .map(|&v| {
                                    let p = block.vertices()[v];
                                    self.screen([p.x, p.y, p.z])
                                })
                                .collect(),
                            colour: RGBColor(s(r), s(g), s(b)),
                        });
                    }
                }
                patches.sort_by(|a, b| a.depth.total_cmp(&b.depth));
                order_by_planes(&mut patches);
            }
        }
        patches
    }

    /// Closed contacts as lines along their normals, 6 % of the picture's
    /// height at the run's typical normal force, at most twice that.
    fn force_lines(&self, posed: &Posed, run: &RunData, k: usize, largest: f64) -> Vec<ForceLine> {
        let Some(contacts) = run.contacts.as_ref().map(|c| &c[k]) else {
            return Vec::new();
        };
        if largest <= 0.0 {
            return Vec::new();
        }
        let full = 0.06 * self.height / self.scale;
        let polyhedra: Vec<&Polyhedron> = match posed {
            Posed::Space(b) => b.iter().collect(),
            Posed::Plane(_) => Vec::new(),
        };
        let mut lines = Vec::new();
        for c in contacts
            .iter()
            .filter(|c| c.state != ContactState::Open && c.normal_force > 0.0)
        {
            let placed = match posed {
                Posed::Plane(blocks) => contact_2d(&c.contact, blocks)
                    .map(|(p, n)| ([p.x, p.y, 0.0], [n[0], n[1], 0.0])),
                Posed::Space(_) => contact_point_3d(&c.contact, &polyhedra)
                    .zip(contact_normal_3d(&c.contact, &polyhedra))
                    .map(|(p, n)| ([p.x, p.y, p.z], [n.x, n.y, n.z])),
            };
            let Some((p, n)) = placed else { continue };
            let half = 0.5 * full * (c.normal_force / largest).min(2.0);
            let end = |s: f64| self.screen([p[0] + s * n[0], p[1] + s * n[1], p[2] + s * n[2]]);
            lines.push(ForceLine {
                from: end(-half),
                to: end(half),
                sliding: c.state == ContactState::Sliding,
            });
        }
        lines
    }
}

/// Faces at most this many are ordered by their planes, not only by depth.
const MAX_ORDERED_FACES: usize = 1500;

/// Painter's order fixed where depth alone is wrong: a block resting on a
/// large face has face centroids behind that face's, yet lies in front of
/// its plane. A face drawn later that the earlier one lies wholly in front
/// of, while it does not lie wholly in front of the earlier one, moves
/// before it.
fn order_by_planes(patches: &mut Vec<Patch>) {
    if patches.len() > MAX_ORDERED_FACES {
        return;
    }
    let size = patches
        .iter()
        .flat_map(|p| &p.corners)
        .map(|c| c.amax())
        .fold(0.0, f64::max);
    // Blocks in contact overlap by their springs' give: a face resting on
    // another is still in front of it.
    let tol = 1e-4 * size.max(1e-12);
    let in_front = |of: &Patch, face: &Patch| {
        let Some((n, p0)) = of.plane else { return true };
        face.corners.iter().all(|c| n.dot(&(c - p0)) >= -tol)
    };
    let overlap = |a: &Patch, b: &Patch| {
        let bounds = |p: &Patch| {
            p.points.iter().fold(
                [
                    f64::INFINITY,
                    f64::INFINITY,
                    f64::NEG_INFINITY,
                    f64::NEG_INFINITY,
                ],
                |b, q| [b[0].min(q.0), b[1].min(q.1), b[2].max(q.0), b[3].max(q.1)],
            )
        };
        let (a, b) = (bounds(a), bounds(b));
        a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3]
    };
    for _ in 0..patches.len() {
        let mut moved = false;
        'scan: for i in 0..patches.len() {
            for j in i + 1..patches.len() {
                let (a, b) = (&patches[i], &patches[j]);
                if overlap(a, b) && in_front(b, a) && !in_front(a, b) {
                    let later = patches.remove(j);
                    patches.insert(i, later);
                    moved = true;
                    break 'scan;
                }
            }
        }
        if !moved {
            break;
        }
    }
}

/// One picture: title, blocks, force lines, colour bar.
fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    patches: &[Patch],
    lines: &[ForceLine],
    run: &RunData,
    k: usize,
    field: ColorField,
    scale: f64,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let fail = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("cannot draw frame {k}: {e:?}");
    let px = |p: &(f64, f64)| (p.0.round() as i32, p.1.round() as i32);
    root.fill(&WHITE).map_err(fail)?;
    for patch in patches {
        let points: Vec<_> = patch.points.iter().map(px).collect();
        root.draw(&Polygon::new(points.clone(), patch.colour.filled()))
            .map_err(fail)?;
        let mut outline = points;
        outline.push(outline[0]);
        root.draw(&PathElement::new(
            outline,
            RGBColor(40, 40, 40).stroke_width(1),
        ))
        .map_err(fail)?;
    }
    for line in lines {
        let colour = if line.sliding {
            RGBColor(220, 30, 30)
        } else {
            RGBColor(0, 0, 0)
        };
        root.draw(&PathElement::new(
            vec![px(&line.from), px(&line.to)],
            colour.stroke_width(2),
        ))
        .map_err(fail)?;
    }
    let font = |size: f64| (FAMILY, size).into_font().color(&BLACK);
    let (w, h) = root.dim_in_pixel();
    let title = format!("t = {:.3} s", run.times[k]);
    root.draw(&Text::new(title, (MARGIN as i32, 10), font(20.0)))
        .map_err(fail)?;
    if run.contacts.is_some() {
        let note = "contact force lines: black locked, red sliding";
        root.draw(&Text::new(note, (MARGIN as i32 + 150, 14), font(14.0)))
            .map_err(fail)?;
    }
    // The colour bar: 0 at the bottom, the run's largest value at the top.
    let (x0, x1) = (w as i32 - RIGHT as i32 + 15, w as i32 - RIGHT as i32 + 35);
    let (y0, y1) = (TOP as i32 + 20, h as i32 - MARGIN as i32 - 20);
    root.draw(&Text::new(
        field.label(),
        (x0 - 10, TOP as i32 - 2),
        font(13.0),
    ))
    .map_err(fail)?;
    if field == ColorField::Block {
        return root.present().map_err(fail);
    }
    let steps = 64;
    for j in 0..steps {
        let t = j as f64 / steps as f64;
        let ya = y1 - ((y1 - y0) as f64 * (j + 1) as f64 / steps as f64).round() as i32;
        let yb = y1 - ((y1 - y0) as f64 * t).round() as i32;
        let (r, g, b) = viridis(t + 0.5 / steps as f64);
        root.draw(&Rectangle::new(
            [(x0, ya), (x1, yb)],
            RGBColor(r, g, b).filled(),
        ))
        .map_err(fail)?;
    }
    root.draw(&Rectangle::new([(x0, y0), (x1, y1)], BLACK.stroke_width(1)))
        .map_err(fail)?;
    for (value, y) in [(scale, y0), (scale / 2.0, (y0 + y1) / 2), (0.0, y1)] {
        root.draw(&Text::new(short(value), (x1 + 5, y - 7), font(13.0)))
            .map_err(fail)?;
    }
    root.present().map_err(fail)
}

/// A colour-bar label.
fn short(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 {
        "0".into()
    } else if (1e-2..1e4).contains(&a) {
        format!("{v:.3}")
    } else {
        format!("{v:.2e}")
    }
}

#[cfg(test)]
mod tests {
    use super::choose_frames;

    #[test]
    fn frames_are_spread_from_first_to_last() {
        assert_eq!(choose_frames(5, None).unwrap(), vec![0, 1, 2, 3, 4]);
        assert_eq!(choose_frames(61, Some(3)).unwrap(), vec![0, 30, 60]);
        assert_eq!(choose_frames(61, Some(1)).unwrap(), vec![60]);
        assert!(choose_frames(5, Some(6)).is_err());
        assert!(choose_frames(5, Some(0)).is_err());
    }
}
