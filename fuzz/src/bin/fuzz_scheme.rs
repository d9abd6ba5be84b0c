//! AFL target: [`tessgen_fuzz::scheme`].
fn main() {
    afl::fuzz!(|data: &[u8]| {
        tessgen_fuzz::scheme(data);
    });
}
