// planted: not as .clang-format writes it (format_lint_catches_planted)
int  planted ( int a ){return a+1 ;}
