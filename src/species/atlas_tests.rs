//! Tests of the leaf atlas (`atlas.rs`).

use super::*;

/// The opaque islands of the atlas's texels inside `cell` (4- and diagonal neighbours join).
fn islands(a: &Atlas, cell: &Cell) -> usize {
    let s = a.size as usize;
    let (x0, y0) = ((cell.uv[0].x * s as f32) as usize, (cell.uv[0].y * s as f32) as usize);
    let (x1, y1) = ((cell.uv[1].x * s as f32) as usize, (cell.uv[1].y * s as f32) as usize);
    let mut seen = vec![false; s * s];
    let mut count = 0;
    for y in y0..y1 {
        for x in x0..x1 {
            if seen[y * s + x] || a.image.get_pixel(x as u32, y as u32)[3] == 0 {
                continue;
            }
            count += 1;
            let mut stack = vec![(x, y)];
            seen[y * s + x] = true;
            while let Some((cx, cy)) = stack.pop() {
                for (dx, dy) in [(-1i64, -1i64), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1)] {
                    let (nx, ny) = (cx as i64 + dx, cy as i64 + dy);
                    if nx < x0 as i64 || ny < y0 as i64 || nx >= x1 as i64 || ny >= y1 as i64 {
                        continue;
                    }
                    let (nx, ny) = (nx as usize, ny as usize);
                    if !seen[ny * s + nx] && a.image.get_pixel(nx as u32, ny as u32)[3] != 0 {
                        seen[ny * s + nx] = true;
                        stack.push((nx, ny));
                    }
                }
            }
        }
    }
    count
}

#[test]
fn every_leaf_of_a_card_or_spray_is_its_own_island() {
    for name in ["oak", "birch", "beech", "scots_pine", "norway_spruce", "shrub"] {
        let (_, p) = crate::species::preset::load(name).unwrap();
        let a = atlas(&p);
        for (what, cell) in [("card", &a.card), ("spray 1", &a.sprays[0]), ("spray 2", &a.sprays[1])] {
            assert_eq!(islands(&a, cell), cell.leaves, "{name}: {what}");
        }
        assert!(
            a.sprays[0].leaves as f32 >= 0.8 * p.spray_leaves as f32,
            "{name}: {} of {} leaves fitted",
            a.sprays[0].leaves,
            p.spray_leaves
        );
        assert!(
            a.card.leaves as f32 >= 0.8 * p.card_leaves as f32,
            "{name}: {} of {} on the card",
            a.card.leaves,
            p.card_leaves
        );
    }
}
