fn main() {
    std::process::exit(prism::cli::main());
}
