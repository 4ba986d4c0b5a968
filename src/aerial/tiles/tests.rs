//! Tests of the pyramid writer and reader on small images made here, checked against values
//! computed directly from the images' texels.

use std::path::Path;

use super::*;
use crate::aerial::AerialError;
use crate::aerial::raster::write_png;

/// A texel pattern that differs at every texel and channel.
fn texel(x: u32, y: u32, k: u32) -> u8 {
    ((x * 31 + y * 17 + k * 101 + (x * y) % 13) % 256) as u8
}

fn make_image(path: &Path, w: u32, h: u32, ch: u8) -> Vec<u8> {
    let mut data = Vec::new();
    for y in 0..h {
        for x in 0..w {
            for k in 0..ch as u32 {
                data.push(texel(x, y, k));
            }
        }
    }
    write_png(path, w, h, ch, &data).unwrap();
    data
}

fn tile(src: &Path, out: &Path, size: u32, force: bool) -> Result<PyramidMeta, String> {
    tile_image(src, out, TileOptions { tile: size, force }, &|_, _| {}).map_err(|e| e.to_string())
}

#[test]
fn mip_zero_tiles_hold_the_image_and_alpha_marks_the_outside() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (300u32, 200u32);
    let img = dir.path().join("a.png");
    let data = make_image(&img, w, h, 3);
    let out = dir.path().join("pyr");
    let meta = tile(&img, &out, 64, false).unwrap();
    // 300 → 150 → 75 → 38: the fourth mip is the first to fit a tile of 64.
    assert_eq!((meta.width, meta.height, meta.channels, meta.tile, meta.levels), (300, 200, 3, 64, 4));
    let line = (w * 3) as usize;
    assert_eq!(meta.fingerprint, fingerprint(w, h, 3, &data[..line], &data[data.len() - line..]));
    let p = Pyramid::open(&out).unwrap();
    assert_eq!(p.meta(), &meta);
    // An inner tile: every texel equals the source's, alpha 255.
    let t = p.read_tile(0, 1, 2).unwrap();
    assert_eq!(t.len(), 64 * 64 * 4);
    for (y, x) in [(0u32, 0u32), (5, 63), (63, 17), (40, 40)] {
        let (sx, sy) = (64 + x, 128 + y);
        let d = ((y * 64 + x) * 4) as usize;
        assert_eq!(&t[d..d + 4], &[texel(sx, sy, 0), texel(sx, sy, 1), texel(sx, sy, 2), 255]);
    }
    // The bottom-right tile holds 300 − 256 = 44 columns and 200 − 192 = 8 rows.
    let t = p.read_tile(0, 4, 3).unwrap();
    let at = |x: usize, y: usize| &t[(y * 64 + x) * 4..(y * 64 + x) * 4 + 4];
    assert_eq!(at(43, 7), &[texel(299, 199, 0), texel(299, 199, 1), texel(299, 199, 2), 255]);
    assert_eq!(at(44, 0), &[0, 0, 0, 0], "outside the image: alpha 0");
    assert_eq!(at(0, 8), &[0, 0, 0, 0]);
    assert!(p.read_tile(0, 5, 0).is_err(), "a tile past the grid is an error");
    assert!(p.read_tile(4, 0, 0).is_err(), "a mip past the top is an error");
}

#[test]
fn coarser_mips_are_rounded_means_of_the_texels_below() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (150u32, 70u32);
    let img = dir.path().join("g.png");
    make_image(&img, w, h, 1);
    let out = dir.path().join("pyr");
    let meta = tile(&img, &out, 32, false).unwrap();
    // 150 x 70 → 75 x 35 → 38 x 18 → 19 x 9: four mips.
    assert_eq!(meta.levels, 4);
    let p = Pyramid::open(&out).unwrap();
    // Mip 1 texel (u, v) = round(mean of mip 0's (2u..2u+1, 2v..2v+1)).
    let mean4 = |u: u32, v: u32| {
        let s: u32 = [(0, 0), (1, 0), (0, 1), (1, 1)].iter().map(|&(a, b)| texel(2 * u + a, 2 * v + b, 0) as u32).sum();
        ((s + 2) / 4) as u8
    };
    let t = p.read_tile(1, 1, 0).unwrap();
    for (u, v) in [(32u32, 0u32), (40, 17), (63, 31)] {
        let d = (((v * 32) + (u - 32)) * 4) as usize;
        assert_eq!(t[d], mean4(u, v), "mip 1 texel ({u}, {v})");
        assert_eq!((t[d + 1], t[d + 2], t[d + 3]), (t[d], t[d], 255), "grey is spread to RGB");
    }
    // Mip 2's last column (u = 37) sits over mip 1's single column 74: the mean of two texels,
    // each of which is the mean of four of mip 0.
    let t2 = p.read_tile(2, 1, 0).unwrap();
    let v = 3u32;
    let expect = ((mean4(74, 2 * v) as u32 + mean4(74, 2 * v + 1) as u32 + 1) / 2) as u8;
    assert_eq!(t2[((v * 32 + (37 - 32)) * 4) as usize], expect);
    assert_eq!(t2[((v * 32 + (38 - 32)) * 4 + 3) as usize], 0, "column 38 is outside mip 2 (38 wide)");
}

#[test]
fn an_existing_pyramid_is_kept_without_force_and_replaced_with_it() {
    let dir = tempfile::tempdir().unwrap();
    let a = dir.path().join("a.png");
    let b = dir.path().join("b.png");
    make_image(&a, 40, 40, 3);
    make_image(&b, 50, 20, 1);
    let out = dir.path().join("pyr");
    let first = tile(&a, &out, 16, false).unwrap();
    let e = tile(&b, &out, 16, false).unwrap_err();
    assert!(e.contains("--force"), "{e}");
    assert_eq!(Pyramid::open(&out).unwrap().meta(), &first, "the old pyramid is untouched");
    let second = tile(&b, &out, 16, true).unwrap();
    assert_eq!(Pyramid::open(&out).unwrap().meta(), &second);
    // A folder with other content is never replaced, even with --force.
    let other = dir.path().join("photos");
    std::fs::create_dir(&other).unwrap();
    std::fs::write(other.join("keep.txt"), b"mine").unwrap();
    assert!(tile(&a, &other, 16, true).unwrap_err().contains("not a pyramid"));
    assert_eq!(std::fs::read(other.join("keep.txt")).unwrap(), b"mine");
    // Nothing but the inputs and outputs is left behind (no temporary folders).
    let mut names: Vec<String> =
        std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    assert_eq!(names, ["a.png", "b.png", "photos", "pyr"]);
}

#[test]
fn a_damaged_image_leaves_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let img = dir.path().join("a.png");
    make_image(&img, 64, 64, 3);
    let bytes = std::fs::read(&img).unwrap();
    std::fs::write(&img, &bytes[..bytes.len() / 2]).unwrap();
    let out = dir.path().join("pyr");
    let e = tile(&img, &out, 16, false).unwrap_err();
    assert!(!e.contains('\n') && e.contains("a.png"), "{e}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1, "neither the pyramid nor a temporary folder");
}

#[test]
fn missing_truncated_and_foreign_tiles_and_pyramids_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let img = dir.path().join("a.png");
    make_image(&img, 100, 100, 3);
    let out = dir.path().join("pyr");
    let meta = tile(&img, &out, 32, false).unwrap();
    let p = Pyramid::open(&out).unwrap();
    let one_line = |e: AerialError| {
        let e = e.to_string();
        assert!(!e.contains('\n') && !e.is_empty());
        e
    };
    // Missing.
    std::fs::remove_file(tile_path(&out, 0, 1, 1)).unwrap();
    assert!(one_line(p.read_tile(0, 1, 1).unwrap_err()).contains("tile (1, 1) of mip 0"));
    // Truncated.
    let path = tile_path(&out, 0, 2, 0);
    let bytes = std::fs::read(&path).unwrap();
    std::fs::write(&path, &bytes[..bytes.len() * 2 / 3]).unwrap();
    one_line(p.read_tile(0, 2, 0).unwrap_err());
    // A tile of another size put in its place (the edge tile is 100 − 96 = 4 wide).
    std::fs::copy(tile_path(&out, 0, 0, 0), tile_path(&out, 0, 3, 0)).unwrap();
    assert!(one_line(p.read_tile(0, 3, 0).unwrap_err()).contains("does not belong"));
    // A pyramid from another image.
    let e = Pyramid::open_expecting(&out, "0123456789abcdef").unwrap_err();
    assert!(one_line(e).contains("another image"));
    assert!(Pyramid::open_expecting(&out, &meta.fingerprint).is_ok());
    // A damaged or missing description.
    std::fs::write(out.join(META_FILE), "(format: \"grove-pyramid\", version: 1, width: 5").unwrap();
    one_line(Pyramid::open(&out).unwrap_err());
    std::fs::remove_file(out.join(META_FILE)).unwrap();
    one_line(Pyramid::open(&out).unwrap_err());
    one_line(Pyramid::open(&dir.path().join("nowhere")).unwrap_err());
}
