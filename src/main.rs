fn main() {
    println!("prism");
}
