use clap::Parser;

fn main() {
    let cli = texopt::cli::Cli::parse();
    std::process::exit(texopt::cli::main_with(cli));
}
