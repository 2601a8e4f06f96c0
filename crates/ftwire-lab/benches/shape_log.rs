//! Throughput of `ftwire shape --log --out`: a simulated rig log of 2 000 records read,
//! mapped and shaped (100 points, stability, the jump flag, the inner markers' distance) and
//! written as `shapes.jsonl`, in records per second (target: at least 20 000).
//!
//! The log: stable configurations of the 2 mm nitinol wire sampled in normalised units in
//! `[−10, 10]⁶` (fixed seed), each written as the `raw` reading the default mounting gives
//! (force first, sensor frame) with 11 markers on its shape, read back through `--mounting`.
//!
//! `cargo bench -p ftwire-lab --bench shape_log -- --warm-up-time 1 --measurement-time 5`
#![allow(missing_docs)]

use std::hint::black_box;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use ftwire_estimate::ft::MountingSpec;
use ftwire_estimate::log::{LogRecord, to_line};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_lab::log::shape::{DEFAULT_POINTS, ShapeLog, ShapeLogParams};
use ftwire_lab::wire::WireSpec;
use ftwire_rod::sampling::Sampler;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const RECORDS: usize = 2000;
const WIRE: &str = "nitinol-2mm-630";

/// Writes the simulated log into `dir` and returns its path.
fn simulated_log(dir: &Path) -> Result<PathBuf, Box<dyn std::error::Error>> {
    let wire = WireSpec::load(WIRE)?.wire_params()?;
    let model = KirchhoffModel::new(wire);
    let mounting = MountingSpec::default().mounting()?;
    let sampler = Sampler::new(10.0)?;
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut text = String::from("# a simulated rig log\n");
    for i in 0..RECORDS {
        let a = sampler.sample_stable(model.rod(), &mut rng)?;
        let shape = model.shape(&a, 11)?;
        #[allow(clippy::cast_precision_loss)] // a few thousand records
        let record = LogRecord {
            time: 0.1 * i as f64,
            raw: Some(mounting.to_sensor(&a).into()),
            a: None,
            b: None,
            markers: Some(
                shape
                    .positions
                    .iter()
                    .map(|p| Some([p.x, p.y, p.z]))
                    .collect(),
            ),
            gravity: None,
        };
        text.push_str(&to_line(&record)?);
        text.push('\n');
    }
    let path = dir.join("rig.jsonl");
    std::fs::write(&path, text)?;
    Ok(path)
}

fn bench(c: &mut Criterion) {
    let dir = std::env::temp_dir().join(format!("ftwire-bench-shape-log-{}", std::process::id()));
    if std::fs::create_dir_all(&dir).is_err() {
        return;
    }
    let Ok(log) = simulated_log(&dir) else {
        return;
    };
    let params = ShapeLogParams {
        mounting: Some(MountingSpec::default()),
        points: DEFAULT_POINTS,
        ..ShapeLogParams::new(log, WIRE)
    };
    let out = dir.join("shapes.jsonl");
    let mut group = c.benchmark_group("shape --log --out");
    group.sample_size(20);
    group.throughput(Throughput::Elements(RECORDS as u64));
    group.bench_function("2000 records, 100 points, read + shape + write", |b| {
        b.iter(|| {
            let run = ShapeLog::load(&params).and_then(|shapes| {
                let file = std::fs::File::create(&out)
                    .map_err(|e| ftwire_lab::LabError::io("shapes.jsonl", e))?;
                shapes.write_shapes(&mut BufWriter::new(file), &mut |_| {})
            });
            black_box(run)
        });
    });
    group.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, bench);
criterion_main!(benches);
