fn main() {
    for a in realtime::adapters() {
        println!("{a}");
    }
}
