//! The `hyst` command-line tool.

fn main() {
    println!("hyst");
}
