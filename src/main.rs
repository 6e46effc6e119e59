fn main() {
    let cli = axterm::cli::links::parse();
    std::process::exit(axterm::cli::run(cli));
}
