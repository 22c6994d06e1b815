//! `traxer info`: what this build runs on.

/// Show the traxer build, the linked Embree library and the machine.
#[derive(clap::Args)]
pub struct InfoArgs {
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: InfoArgs) -> anyhow::Result<()> {
    let device = traxer::embree::Device::new()?;
    let e = device.info();
    let isa = match e.native_packets.iter().max() {
        Some(16) => "AVX-512 (native 16-wide packets)",
        Some(8) => "AVX/AVX2 (native 8-wide packets)",
        Some(4) => "SSE (native 4-wide packets)",
        _ => "scalar",
    };
    let mut cpu = Vec::new();
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("sse4.2") {
            cpu.push("sse4.2");
        }
        if std::arch::is_x86_feature_detected!("avx") {
            cpu.push("avx");
        }
        if std::arch::is_x86_feature_detected!("avx2") {
            cpu.push("avx2");
        }
        if std::arch::is_x86_feature_detected!("avx512f") {
            cpu.push("avx512f");
        }
    }
    let threads = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1);
    if a.json {
        let v = serde_json::json!({
            "traxer_version": env!("CARGO_PKG_VERSION"),
            "git_hash": traxer::output::git_hash(),
            "embree": e,
            "embree_isa": isa,
            "cpu_features": cpu,
            "threads": threads,
        });
        say!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        say!(
            "traxer {} ({})",
            env!("CARGO_PKG_VERSION"),
            traxer::output::git_hash()
        );
        say!(
            "Embree {} (API {}), tasking: {}",
            e.version,
            e.major,
            e.tasking_system
        );
        say!("Embree ISA: {isa}; robust scenes: yes");
        say!("CPU features: {}", cpu.join(" "));
        say!("threads (default for --threads 0): {threads}");
    }
    Ok(())
}
