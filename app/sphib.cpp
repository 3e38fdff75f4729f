// The sphib command (stub until the run/check/sweep commands land).
#include <cstdio>
int main() { std::puts("sphib: under construction"); return 0; }
