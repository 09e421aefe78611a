//! The `twin` command line.
fn main() {
    println!("twin: the scenario runner is being built; see README.md");
}
