use clap::Parser;

fn main() {
    // A closed stdout or stderr (`texopt … | head`) ends the program quietly, as it ends
    // other Unix tools, instead of a panic on the next print; finished study cases are
    // already in the cache.
    sigpipe::reset();
    let cli = texopt::cli::Cli::parse();
    std::process::exit(texopt::cli::main_with(cli));
}
