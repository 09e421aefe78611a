//! Prints the mutant of one fuzz case (see `twin/tests/fuzz_cases`):
//! `cargo run -p twin --example fuzz_show -- N`. The first line names the
//! file it was made from.

#[allow(dead_code)] // the fuzz cases use a part
#[path = "../tests/common/mod.rs"]
mod common;
#[path = "../tests/fuzz_cases/mod.rs"]
mod fuzz_cases;

fn main() {
    let n: u64 = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(0);
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let corpus = fuzz_cases::Corpus::load(&root);
    match fuzz_cases::mutant_of(&corpus, n) {
        Some((from, text)) => print!("{}\n{text}", from.display()),
        None => println!("case {n} mutates a binary STL"),
    }
}
