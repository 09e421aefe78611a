//! Writes a large Studio 5000 export and a scene naming it, for the L5X
//! load benchmark (README, *Benchmarks*):
//!
//! ```text
//! cargo run --release -p twin --example l5x_generate -- target/l5x_big
//! time target/release/twin check target/l5x_big/big.toml
//! ```
//!
//! The export has 10,000 controller tags (REAL[16] arrays with L5K and
//! Decorated data), 50 programs of 10 ST routines each (500 routines of
//! 750 lines, every line an assignment between tags), a periodic task
//! scheduling them, and comes to 50 MB. Arguments: the folder, then
//! optionally the tag count, the routine count and the lines a routine.

use std::fmt::Write as _;
use std::path::PathBuf;

fn main() {
    let mut args = std::env::args().skip(1);
    let dir = PathBuf::from(args.next().unwrap_or_else(|| "target/l5x_big".to_owned()));
    let tags: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(10_000);
    let routines: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(500);
    let per_program = 10;
    let lines: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(750);
    std::fs::create_dir_all(&dir).expect("create the folder");

    let mut x = String::with_capacity(60 << 20);
    x.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"yes\"?>\r\n");
    x.push_str("<RSLogix5000Content SchemaRevision=\"1.0\" SoftwareRevision=\"35.00\" TargetName=\"Big\" TargetType=\"Controller\" ContainsContext=\"false\">\r\n");
    x.push_str("<Controller Use=\"Target\" Name=\"Big\" ProcessorType=\"1756-L85E\" MajorRev=\"35\" MinorRev=\"11\">\r\n<Tags>\r\n");
    for t in 0..tags {
        let _ = write!(
            x,
            "<Tag Name=\"T{t}\" TagType=\"Base\" DataType=\"REAL\" Dimensions=\"16\" Radix=\"Float\" Constant=\"false\" ExternalAccess=\"Read/Write\">\r\n<Data Format=\"L5K\">\r\n<![CDATA[["
        );
        for k in 0..16 {
            let _ = write!(x, "{}{:.8e}", if k > 0 { "," } else { "" }, (t * 16 + k) as f64 * 0.001);
        }
        x.push_str("]]]>\r\n</Data>\r\n<Data Format=\"Decorated\">\r\n<Array DataType=\"REAL\" Dimensions=\"16\" Radix=\"Float\">\r\n");
        for k in 0..16 {
            let _ = write!(
                x,
                "<Element Index=\"[{k}]\" Value=\"{}\"/>\r\n",
                (t * 16 + k) as f64 * 0.001
            );
        }
        x.push_str("</Array>\r\n</Data>\r\n</Tag>\r\n");
    }
    x.push_str("</Tags>\r\n<Programs>\r\n");
    let programs = routines.div_ceil(per_program);
    for p in 0..programs {
        let _ = write!(
            x,
            "<Program Name=\"P{p}\" TestEdits=\"false\" MainRoutineName=\"R0\" Disabled=\"false\" UseAsFolder=\"false\">\r\n<Tags>\r\n<Tag Name=\"N\" TagType=\"Base\" DataType=\"DINT\" Radix=\"Decimal\" ExternalAccess=\"Read/Write\">\r\n<Data Format=\"L5K\">\r\n<![CDATA[0]]>\r\n</Data>\r\n</Tag>\r\n</Tags>\r\n<Routines>\r\n"
        );
        for r in 0..per_program.min(routines - p * per_program) {
            let _ = write!(x, "<Routine Name=\"R{r}\" Type=\"ST\">\r\n<STContent>\r\n");
            for l in 0..lines {
                let a = (p * 7919 + r * 104_729 + l * 31) % tags;
                let b = (a * 13 + 7) % tags;
                let body = if l == 0 && r + 1 < per_program {
                    format!("JSR(R{}, 0);", r + 1)
                } else {
                    format!(
                        "T{a}[{}] := T{b}[{}] * 0.5 + T{a}[{}] - 1.25;   // line {l}",
                        l % 16,
                        (l + 3) % 16,
                        (l + 5) % 16
                    )
                };
                let _ = write!(x, "<Line Number=\"{l}\">\r\n<![CDATA[{body}]]>\r\n</Line>\r\n");
            }
            x.push_str("</STContent>\r\n</Routine>\r\n");
        }
        x.push_str("</Routines>\r\n</Program>\r\n");
    }
    x.push_str("</Programs>\r\n<Tasks>\r\n<Task Name=\"Main\" Type=\"PERIODIC\" Rate=\"10\" Priority=\"10\" Watchdog=\"500\" InhibitTask=\"false\">\r\n<ScheduledPrograms>\r\n");
    for p in 0..programs {
        let _ = write!(x, "<ScheduledProgram Name=\"P{p}\"/>\r\n");
    }
    x.push_str("</ScheduledPrograms>\r\n</Task>\r\n</Tasks>\r\n</Controller>\r\n</RSLogix5000Content>\r\n");
    std::fs::write(dir.join("big.L5X"), &x).expect("write the export");

    let urdf = std::env::current_dir()
        .unwrap_or_default()
        .join("scenes/robots/scara/scara.urdf");
    let scene = format!(
        "name = \"big\"\nduration_s = 0.1\ncoarse_update_ms = 4.0\nphysics_step_ms = 1.0\n\n[robot]\nurdf = {:?}\n\n[controller]\nl5x = \"big.L5X\"\n",
        urdf.display().to_string()
    );
    std::fs::write(dir.join("big.toml"), scene).expect("write the scene");
    println!(
        "{}: {:.1} MB, {tags} tags, {routines} routines of {lines} lines",
        dir.join("big.L5X").display(),
        x.len() as f64 / 1e6
    );
}
