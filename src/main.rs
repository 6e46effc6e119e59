use clap::Parser;

fn main() {
    let cli = axterm::cli::Cli::parse();
    std::process::exit(axterm::cli::run(cli));
}
