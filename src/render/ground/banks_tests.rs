use super::*;
use crate::render::ground::landscape::KIND_FLOOR;
use grove_systems::plane_geometry::plane_geometry;
use grove_systems::scene::{Hole, PlaneShape};

/// A vertex's position.
fn pos(v: &[f32; 8]) -> Vec3 {
    Vec3::new(v[0], v[1], v[2])
}

/// The quads of `mesh` (four vertices each, as `LandMesh::quad` adds them): corners, normal, kind.
fn quads(mesh: &LandMesh) -> Vec<([Vec3; 4], Vec3, f32)> {
    mesh.vertices
        .chunks(4)
        .map(|q| ([pos(&q[0]), pos(&q[1]), pos(&q[2]), pos(&q[3])], Vec3::new(q[0][3], q[0][4], q[0][5]), q[0][6]))
        .collect()
}

/// Every triangle's front faces its vertices' normal.
fn fronts_face_normals(mesh: &LandMesh) {
    for tri in mesh.indices.chunks(3) {
        let v: Vec<&[f32; 8]> = tri.iter().map(|&i| &mesh.vertices[i as usize]).collect();
        let n = Vec3::new(v[0][3], v[0][4], v[0][5]);
        assert!(
            (pos(v[1]) - pos(v[0])).cross(pos(v[2]) - pos(v[0])).dot(n) > 0.0,
            "a triangle faces away from its normal {n}"
        );
    }
}

/// A 2 m square at height `y`, two triangles, counter-clockwise from above.
fn square(y: f32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    (
        vec![Vec3::new(0.0, y, 0.0), Vec3::new(2.0, y, 0.0), Vec3::new(2.0, y, 2.0), Vec3::new(0.0, y, 2.0)],
        vec![[0, 3, 1], [1, 3, 2]],
    )
}

#[test]
fn a_raised_square_stands_on_a_bank_whose_foot_lies_out_by_its_slope() {
    // The square 1 m up, the terrain at 0, the floor at -0.6.
    let (v, t) = square(1.0);
    let floor_y = -0.6;
    let (found, stray) = rims(&v, &t);
    assert!(stray.is_empty());
    assert_eq!(found.len(), 1);
    assert!(!found[0].hole, "the square's outline taken for a hole");
    let mut m = LandMesh::default();
    sides(&mut m, &v, &t, floor_y);
    fronts_face_normals(&m);
    let q = quads(&m);
    // Per edge a soil cut and a grassed slope.
    assert_eq!(q.iter().filter(|q| q.2 == KIND_SIDE).count(), 4);
    assert_eq!(q.iter().filter(|q| q.2 == KIND_BANK).count(), 4);
    // How far outside the square a point lies (0 on or inside it).
    let outside = |p: Vec3| (Vec2::ZERO - xz(p)).max(xz(p) - Vec2::splat(2.0)).max(Vec2::ZERO).length();
    let lip_out = SOIL_EDGE * SOIL_EDGE_RUN;
    for (corners, normal, kind) in &q {
        // Every side faces up and out of the square.
        let out = xz(corners.iter().sum::<Vec3>() / 4.0) - Vec2::ONE;
        assert!(normal.y > 0.0 && xz(*normal).dot(out) > 0.0, "{normal} at {corners:?}");
        for p in corners {
            if *kind == KIND_SIDE {
                // The soil cut: from the edge down SOIL_EDGE, out by its own slope.
                assert!(p.y == 1.0 && outside(*p) == 0.0 || (p.y - (1.0 - SOIL_EDGE)).abs() < 1e-6, "{p}");
            } else if p.y == floor_y {
                // The bank's foot lies out from the edge by the slope times the drop from the
                // lip to the floor (on a corner, along its mitre: out by that along both axes).
                let run = lip_out + (1.0 - SOIL_EDGE - floor_y) * BANK_RUN;
                let d = (xz(*p) - Vec2::ONE).abs() - Vec2::ONE;
                assert!((d.x - run).abs() < 1e-5 && (d.y - run).abs() < 1e-5, "foot {p}, run {run}");
            }
        }
    }
    // The slope reaches the terrain (y = 0) out by the slope times the bank's height there,
    // not straight down at the edge: along the middle of each edge's bank face.
    for (c, _, kind) in q.iter().filter(|q| q.2 == KIND_BANK) {
        let (lip, foot) = ((c[0] + c[1]) * 0.5, (c[2] + c[3]) * 0.5);
        let at_ground = lip + (foot - lip) * (lip.y / (lip.y - foot.y));
        let expect = lip_out + (1.0 - SOIL_EDGE) * BANK_RUN;
        assert!(
            (outside(at_ground) - expect).abs() < 1e-5,
            "{kind}: meets the ground {} out, not {expect}",
            outside(at_ground)
        );
        assert!(expect > 1.0, "a bank about as wide as it is high, or wider");
    }
}

#[test]
fn a_hole_is_a_pit_whose_walls_slope_in_to_the_floor() {
    let hole = Hole { center: Vec2::new(0.3, -0.2), radius: 1.3 };
    let shape = PlaneShape::Grid {
        min: Vec2::splat(-4.0),
        size: Vec2::splat(8.0),
        cell: 0.5,
        elevation: 0.0,
        unevenness: 0.0,
        noise_seed: 0,
        holes: vec![hole],
    };
    let (v, t) = plane_geometry(&shape);
    let (found, stray) = rims(&v, &t);
    assert!(stray.is_empty(), "{stray:?}");
    assert_eq!(found.len(), 2);
    assert_eq!(found.iter().filter(|r| r.hole).count(), 1, "one outline, one hole");
    let rim = found.iter().find(|r| r.hole).expect("the hole's rim");
    // The rim goes round the hole: every rim vertex lies near the circle.
    for &i in &rim.vertices {
        let d = xz(v[i as usize]).distance(hole.center);
        assert!(d > hole.radius - 0.75 && d < hole.radius + 0.75, "rim vertex {d} m from the centre");
    }
    let floor_y = -0.6;
    let top: Vec<Vec3> = rim.vertices.iter().map(|&i| v[i as usize]).collect();
    let feet = pit_feet(&top, &rim.away, floor_y);
    let centre = top.iter().map(|&p| xz(p)).sum::<Vec2>() / top.len() as f32;
    for (p, f) in top.iter().zip(&feet) {
        let (from, to) = (xz(*p).distance(centre), f.distance(centre));
        // Each foot lies inwards of its rim vertex, by the wall's slope times the depth, and
        // at most PIT_REACH of the way to the centre, under the hole.
        let inset = (0.6 * PIT_RUN).min(PIT_REACH * from);
        assert!((from - to - inset).abs() < 1e-4, "foot {to} m from the centre, its rim vertex {from} m");
        assert!(from - to > 0.2, "a wall too steep to read as sloped");
        assert!(inside(*f, &top.iter().map(|&p| xz(p)).collect::<Vec<_>>()), "foot {f} outside the hole");
    }
    // The walls, as sides draws them: soil, facing up and into the pit.
    let mut m = LandMesh::default();
    sides(&mut m, &v, &t, floor_y);
    fronts_face_normals(&m);
    let near_hole = |p: Vec3| xz(p).distance(hole.center) < hole.radius + 1.0;
    let walls: Vec<_> = quads(&m).into_iter().filter(|(c, _, _)| c.iter().all(|&p| near_hole(p))).collect();
    assert_eq!(walls.len(), rim.vertices.len());
    for (c, n, kind) in walls {
        assert_eq!(kind, KIND_SIDE);
        assert_ne!(kind, KIND_FLOOR);
        let mid = xz(c.iter().sum::<Vec3>() / 4.0);
        assert!(n.y > 0.2 && xz(n).dot(centre - mid) > 0.0, "wall normal {n} at {mid}");
    }
    // Darker towards the foot: the walls' corners on the floor are shaded, the rim's are not.
    for v in m.vertices.iter().filter(|v| v[6] == KIND_SIDE && near_hole(pos(v))) {
        assert_eq!(v[7], if v[1] == floor_y { PIT_FOOT_SHADE } else { 1.0 }, "{v:?}");
    }
    // The outline of a plane at the terrain's height still gets its bank (under the terrain).
    assert!(quads(&m).iter().any(|q| q.2 == KIND_BANK));
}

/// Whether `p` lies inside the polygon `poly` (even-odd rule).
fn inside(p: Vec2, poly: &[Vec2]) -> bool {
    let mut inside = false;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            inside = !inside;
        }
    }
    inside
}

#[test]
fn the_zigzag_rims_of_the_study_holes_slope_in_under_the_hole() {
    // The study's ground (assets/scenes/study.ron): 1 m cells, so its holes' rims zigzag along
    // the triangles' diagonals and are not star-shaped about their centres.
    let holes = vec![
        Hole { center: Vec2::new(5.5, -4.0), radius: 1.1 },
        Hole { center: Vec2::new(-7.5, -9.0), radius: 1.6 },
        Hole { center: Vec2::new(-2.0, 4.5), radius: 0.8 },
        Hole { center: Vec2::new(10.0, 6.0), radius: 1.3 },
    ];
    let shape = PlaneShape::Grid {
        min: Vec2::splat(-15.0),
        size: Vec2::splat(30.0),
        cell: 1.0,
        elevation: 0.0,
        unevenness: 0.04,
        noise_seed: 7,
        holes,
    };
    let (v, t) = plane_geometry(&shape);
    let (found, stray) = rims(&v, &t);
    assert!(stray.is_empty());
    assert_eq!(found.iter().filter(|r| r.hole).count(), 4);
    for rim in found.iter().filter(|r| r.hole) {
        let top: Vec<Vec3> = rim.vertices.iter().map(|&i| v[i as usize]).collect();
        let feet = pit_feet(&top, &rim.away, -0.64);
        let n = top.len();
        for i in 0..n {
            // Each wall slopes into the pit: both its feet lie on the hole's side of its rim
            // edge (at a spike's tip only a little).
            let (a, b) = (xz(top[i]), xz(top[(i + 1) % n]));
            let line = |f: Vec2| (f - a).dot(rim.away[i]);
            assert!(
                line(feet[i]) > 0.05 && line(feet[(i + 1) % n]) > 0.05,
                "wall {a}-{b} with feet {} {}",
                feet[i],
                feet[(i + 1) % n]
            );
            // Every foot moved well in from its rim vertex.
            assert!(feet[i].distance(a) > 0.25, "foot {} of {a}", feet[i]);
        }
    }
    // As sides draws them: every pit wall faces up (the bank of the outline lies under the
    // terrain, 0.04 m at most above it).
    let mut m = LandMesh::default();
    sides(&mut m, &v, &t, -0.64);
    fronts_face_normals(&m);
    for q in quads(&m).iter().filter(|q| q.2 == KIND_SIDE) {
        assert!(q.1.y > 0.0, "{:?}", q);
    }
}

#[test]
fn rims_that_touch_at_a_vertex_get_vertical_walls() {
    // Two triangles sharing only vertex 0: four boundary edges meet there.
    let v = [
        Vec3::ZERO,
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 1.0),
        Vec3::new(-1.0, 0.0, 0.0),
        Vec3::new(-1.0, 0.0, -1.0),
    ];
    let t = [[0, 2, 1], [0, 4, 3]];
    let (found, stray) = rims(&v, &t);
    assert!(found.is_empty());
    assert_eq!(stray.len(), 6);
    let mut m = LandMesh::default();
    sides(&mut m, &v, &t, -0.6);
    fronts_face_normals(&m);
    for (c, n, kind) in quads(&m) {
        assert_eq!(kind, KIND_SIDE);
        assert_eq!(n.y, 0.0);
        // Straight down: two corners above the other two.
        assert_eq!(xz(c[0]), xz(c[3]));
        assert_eq!(xz(c[1]), xz(c[2]));
    }
}

#[test]
fn a_mitre_moves_both_edges_out_by_one_and_is_bounded() {
    let (x, z) = (Vec2::X, Vec2::Y);
    assert_eq!(mitre(x, x), x);
    let m = mitre(x, z);
    assert!((m - Vec2::ONE).length() < 1e-6 && (m.dot(x) - 1.0).abs() < 1e-6 && (m.dot(z) - 1.0).abs() < 1e-6);
    // A spike: no longer than the limit.
    let sharp = mitre(x, Vec2::new(-0.99, 0.14).normalize());
    assert!(sharp.length() <= MITRE_LIMIT + 1e-5, "{sharp}");
}
