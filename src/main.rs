fn main() {
    std::process::exit(filmsplat::cli::main());
}
