! The lines of a dpmpm_vars_<group>.inc list as the reader's local variables, named as
! in the input; a TEXT string gets a long buffer, so that a value longer than its
! component is seen (and refused) instead of cut.
#undef VAR
#undef TEXT
#undef LOCAL
#define VAR(G, T, N, C, S, V) T :: N S
#define TEXT(G, N, C, L, V, GS, NS) character(len=long_len) :: N
#define LOCAL(G, T, N, S, V) T :: N S
