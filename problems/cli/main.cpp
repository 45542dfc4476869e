#include <iostream>
int main() { std::cout << "tailor\n"; return 0; }
