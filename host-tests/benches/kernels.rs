//! Host benchmarks of the core's kernels and the f64 twin, one process (divan):
//! `cargo bench -p host-tests`. The same kernels run in QEMU under `cargo lab speed`.

use host_tests::commands::speed::{kernels, trace};
use host_tests::oracle::twin;
use imu_core::bench::testsignal::Checksum;

const N: usize = 1 << 16;

fn main() {
    divan::main();
}

#[divan::bench(args = ["pipeline_axis", "pipeline_axis_nofilter", "lowpass", "idsp_lowpass", "integrator_euler", "readout", "f32_pipeline", "narrow_pipeline"], sample_count = 20)]
fn kernel(bencher: divan::Bencher, name: &str) {
    let codes = trace(N);
    let mut k = kernels()
        .into_iter()
        .find(|(n, _)| *n == name)
        .map(|(_, k)| k)
        .expect("a kernel of that name");
    let mut sum = Checksum::default();
    bencher
        .counter(divan::counter::ItemsCount::new(N))
        .bench_local(|| k.run(divan::black_box(&codes), &mut sum));
}

#[divan::bench(sample_count = 20)]
fn f64_twin(bencher: divan::Bencher) {
    let codes = trace(N);
    let mut f = twin::Axis {
        lowpass: Some(twin::Lowpass::ideal(50.0 / 3000.0, 2048.0)),
        bias: 2048.0,
        integrator: twin::Integrator::new(twin::Scheme::Euler),
    };
    bencher
        .counter(divan::counter::ItemsCount::new(N))
        .bench_local(|| {
            for &c in divan::black_box(&codes) {
                f.update(c);
            }
        });
}
