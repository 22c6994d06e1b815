//! `traxer info`: what this build runs on.

/// Show the traxer build, the linked Embree library and the machine.
#[derive(clap::Args)]
pub struct InfoArgs {
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub quiet: super::args::QuietArg,
}

pub fn run(a: InfoArgs) -> anyhow::Result<()> {
    let device = traxer::embree::Device::new()?;
    let e = device.info();
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
    // The library reports the packet widths it was compiled for (16 = AVX-512
    // code paths present); at run time it uses the widest one this CPU runs.
    let compiled = |w: u32| e.native_packets.contains(&w);
    let has = |f: &str| cpu.contains(&f);
    let isa = if compiled(16) && has("avx512f") {
        "AVX-512 (16-wide packets)"
    } else if compiled(8) && has("avx2") {
        "AVX2 (8-wide packets)"
    } else if compiled(8) && has("avx") {
        "AVX (8-wide packets)"
    } else if compiled(4) {
        "SSE (4-wide packets)"
    } else {
        "scalar"
    };
    let threads = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1);
    if a.json {
        let v = serde_json::json!({
            "traxer_version": traxer::run::BUILD.version,
            "git_hash": traxer::run::BUILD.git_hash,
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
            traxer::run::git_hash()
        );
        say!(
            "Embree {} (API {}), tasking: {}",
            e.version,
            e.major,
            e.tasking_system
        );
        say!(
            "Embree compiled for packet widths {:?}; on this CPU it uses {isa}; robust scenes: yes",
            e.native_packets
        );
        say!("CPU features: {}", cpu.join(" "));
        say!("threads (default for --threads 0): {threads}");
    }
    Ok(())
}
