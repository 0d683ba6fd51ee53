// Dev tool for scripts/spy_screenshot.sh (not part of the build).
import java.awt.*;
import java.awt.image.BufferedImage;
import java.io.File;
import javax.imageio.ImageIO;
// Captures the X screen (or the rectangle x y w h) into a PNG: java ScreenShot out.png [x y w h]
public class ScreenShot {
  public static void main(String[] a) throws Exception {
    Dimension d = Toolkit.getDefaultToolkit().getScreenSize();
    Rectangle r = a.length == 5
        ? new Rectangle(Integer.parseInt(a[1]), Integer.parseInt(a[2]), Integer.parseInt(a[3]), Integer.parseInt(a[4]))
        : new Rectangle(0, 0, d.width, d.height);
    ImageIO.write(new Robot().createScreenCapture(r), "png", new File(a[0]));
  }
}
