//! The GPU derivation (wgpu compute, lavapipe without a GPU) gives the same string as the CPU
//! with one and with two threads, on every preset; bush 2 at n = 7 needs three scan levels.
//! Without a wgpu adapter the test fails with a message that says so.

use grove::lsystem::gpu::GpuDeriver;
use grove::lsystem::{Limits, derive, derive_threads, presets};

#[test]
fn gpu_equals_cpu_on_every_preset() {
    let gpu = GpuDeriver::new().unwrap_or_else(|e| {
        panic!("{e}: this test needs a GPU or lavapipe (apt-get install mesa-vulkan-drivers libvulkan1)")
    });
    eprintln!("lsystem_gpu: adapter {}", gpu.adapter());
    let limits = Limits::default();
    for name in presets::names() {
        let g = presets::preset(name).unwrap();
        let mut n = g.n;
        while n > 1 && derive(&g, n, 11, &limits).unwrap().len() > 2_000_000 {
            n -= 1;
        }
        let one = derive_threads(&g, n, 11, &limits, 1).unwrap();
        let two = derive_threads(&g, n, 11, &limits, 2).unwrap();
        let dev = gpu.derive(&g, n, 11, &limits).unwrap();
        assert_eq!(one.hash(), two.hash(), "{name} n = {n}: CPU threads");
        assert_eq!(one.len(), dev.len(), "{name} n = {n}: GPU length");
        assert_eq!(one.hash(), dev.hash(), "{name} n = {n}: GPU string");
    }
    // Step 7 reads 711,532 symbols (177,883 words, past 256 × 256): the scan recurses twice.
    let g = presets::preset("bush2").unwrap();
    let cpu = derive(&g, 7, 0, &limits).unwrap();
    assert_eq!(cpu.len(), 5_692_268);
    assert_eq!(gpu.derive(&g, 7, 0, &limits).unwrap().hash(), cpu.hash());
}

#[test]
fn two_dimensional_dispatches_give_the_same_string() {
    // At most 7 workgroups per dimension: bush 2's step 6 (88,940 symbols in, 22,235 words, 87
    // workgroups) runs as a 7 × 13 grid with idle workgroups at the end, and so does its scan.
    let mut gpu = GpuDeriver::new().unwrap_or_else(|e| panic!("{e}"));
    gpu.set_max_workgroups(7);
    let limits = Limits::default();
    for name in ["bush2", "broadleaf", "abop-f"] {
        let g = presets::preset(name).unwrap();
        let n = if name == "bush2" { 6 } else { g.n };
        assert_eq!(gpu.derive(&g, n, 4, &limits).unwrap().hash(), derive(&g, n, 4, &limits).unwrap().hash(), "{name}");
    }
}

#[test]
fn gpu_refuses_parametric_grammars_and_honours_limits() {
    let gpu = GpuDeriver::new().unwrap_or_else(|e| panic!("{e}"));
    let g = grove::lsystem::Grammar::compile(&grove::lsystem::grammar::Source {
        axiom: "F(1)".into(),
        rules: vec!["F(l) -> F(l*0.8)[+F(l*0.6)]".into()],
        ..Default::default()
    })
    .unwrap();
    let e = gpu.derive(&g, 2, 0, &Limits::default()).unwrap_err().to_string();
    assert!(e.contains("without parameters"), "{e}");
    let g = presets::preset("bush2").unwrap();
    let e = gpu.derive(&g, 5, 0, &Limits { max_symbols: 50_000, max_bytes: u64::MAX }).unwrap_err().to_string();
    // Step 4 gives 1 + 19 (8^4 - 1) / 7 = 11,116 symbols, step 5 88,940.
    assert!(e.contains("step 5") && e.contains("88940"), "{e}");
}
