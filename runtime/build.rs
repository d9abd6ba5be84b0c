//! Dogfooding the build.rs integration: the runtime's CPU kernels are the
//! Rust target of the built-in schemes, generated into OUT_DIR at build time.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let out = std::env::var("OUT_DIR").expect("cargo sets OUT_DIR for build scripts");
    if let Err(e) = tessgen_codegen::Builder::new()
        .builtin_schemes()
        .target(tessgen_codegen::Target::Rust)
        .out_dir(&out)
        .command("tessgen-runtime build.rs (Builder::new().builtin_schemes().target(Rust))")
        .write()
    {
        panic!("tessgen code generation failed: {e}");
    }
}
