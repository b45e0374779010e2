//! What the benches share: the CPU's model, printed before any figure, and interleaved rounds
//! of two runs.

/// The CPU's model name (`/proc/cpuinfo`, else `lscpu`), so that figures from different machines
/// are never read as one; the architecture alone where neither says.
fn cpu_model() -> String {
    let field = |text: &str, key: &str| {
        text.lines().find_map(|line| {
            let (name, value) = line.split_once(':')?;
            (name.trim().eq_ignore_ascii_case(key)).then(|| value.trim().to_string())
        })
    };
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|text| field(&text, "model name"))
        .or_else(|| {
            let out = std::process::Command::new("lscpu").output().ok()?;
            field(&String::from_utf8_lossy(&out.stdout), "Model name")
        })
        .unwrap_or_else(|| format!("unknown {} CPU", std::env::consts::ARCH))
}

/// Prints the CPU's model (`CPU: ...`), first thing in a bench's output.
pub fn print_cpu_model() {
    println!("CPU: {}", cpu_model());
}

/// True when the bench measures (`cargo bench`, which passes `--bench`), not when it is listed
/// (`--list`) or run once as a test (`cargo test --benches`).
pub fn measuring() -> bool {
    let args: Vec<String> = std::env::args().collect();
    args.iter().any(|a| a == "--bench") && !args.iter().any(|a| a == "--list")
}

/// Rounds of [`interleaved`]: `GYROCORE_BENCH_ROUNDS`, else 31.
pub fn rounds() -> usize {
    std::env::var("GYROCORE_BENCH_ROUNDS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(31)
}

/// The calling thread's CPU time [ns]: what it ran, without the time it waited for a core.
pub fn thread_cpu_ns() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes the timespec it is given and nothing else.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 * 1e9 + ts.tv_nsec as f64
}

pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Two runs `a` and `b` of `n` samples each in alternation, [`rounds`] rounds: on a machine
/// shared with other work, criterion's one-after-the-other figures move more between two benches
/// than the difference sought, while within a round both are slowed alike. Prints the medians
/// (ns per sample) and the median of the per-round ratios a/b, by wall time and by the thread's
/// CPU time (which leaves out waiting for a core).
pub fn interleaved(names: [&str; 2], n: usize, a: &mut dyn FnMut(), b: &mut dyn FnMut()) {
    let time = |f: &mut dyn FnMut()| {
        let (wall, cpu) = (std::time::Instant::now(), thread_cpu_ns());
        f();
        (wall.elapsed().as_secs_f64() * 1e9, thread_cpu_ns() - cpu)
    };
    let rounds: Vec<_> = (0..rounds()).map(|_| (time(a), time(b))).collect();
    let per_sample = |ns: f64| ns / n as f64;
    let [name_a, name_b] = names;
    for (clock, pick) in [
        ("wall", (|x: (f64, f64)| x.0) as fn((f64, f64)) -> f64),
        ("thread CPU", |x: (f64, f64)| x.1),
    ] {
        let a = median(rounds.iter().map(|r| per_sample(pick(r.0))).collect());
        let b = median(rounds.iter().map(|r| per_sample(pick(r.1))).collect());
        let ratio = median(rounds.iter().map(|r| pick(r.0) / pick(r.1)).collect());
        println!(
            "interleaved, {} rounds, {clock} time: {name_a} {a:.3} ns/sample, \
             {name_b} {b:.3} ns/sample, ratio {ratio:.3} (median of per-round ratios)",
            rounds.len()
        );
    }
}
