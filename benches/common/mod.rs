//! What the benches share: the CPU's model, printed before any figure.

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
